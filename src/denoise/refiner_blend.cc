#include "denoise/refiner_blend.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "denoise/denoise_metrics.h"
#include "denoise/motion_filters.h"

namespace motionfork {

int RefinerBlendBin(double roughness_cm) {
  int bin = 0;
  while (bin < kRefinerBlendBins - 1 && roughness_cm >= kRefinerBlendEdges[bin]) ++bin;
  return bin;
}

std::string RefinerBlendBinName(int bin) {
  if (bin < 0 || bin >= kRefinerBlendBins)
    throw std::invalid_argument("RefinerBlendBinName: no bin " + std::to_string(bin));
  auto text = [](double x) {
    std::string s = std::to_string(x);
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.') s.pop_back();
    return s;
  };
  const std::string low = bin == 0 ? "0" : text(kRefinerBlendEdges[bin - 1]);
  return bin == kRefinerBlendBins - 1 ? ">= " + low + " cm"
                                      : low + "-" + text(kRefinerBlendEdges[bin]) + " cm";
}

std::vector<double> LocalCorrectionCm(const std::vector<float>& input,
                                      const std::vector<float>& refined, int joints, int half,
                                      bool median_over_joints) {
  if (input.size() != refined.size() || joints < 1 || input.size() % (3 * joints) != 0) {
    throw std::invalid_argument("LocalCorrectionCm: expected two motions [T, " +
                                std::to_string(joints) + ", 3] of the same size");
  }
  const size_t F = 3 * static_cast<size_t>(joints), T = input.size() / F;
  std::vector<double> per_frame(T, 0.0), prefix(T + 1, 0.0), per_joint(joints);
  for (size_t t = 0; t < T; ++t) {
    double sum = 0;
    for (int j = 0; j < joints; ++j) {
      double dd = 0;
      for (size_t k = t * F + 3 * j; k < t * F + 3 * j + 3; ++k) {
        const double d = refined[k] - input[k];
        dd += d * d;
      }
      per_joint[j] = dd;
      sum += dd;
    }
    // squared distance per joint, m^2
    prefix[t + 1] = prefix[t] + (median_over_joints ? MedianInPlace(&per_joint) : sum / joints);
  }
  for (size_t t = 0; t < T; ++t) {
    const size_t a = t >= static_cast<size_t>(half) ? t - half : 0,
                 b = std::min(T, t + static_cast<size_t>(half) + 1);
    per_frame[t] = 100 * std::sqrt((prefix[b] - prefix[a]) / static_cast<double>(b - a));
  }
  return per_frame;
}

std::string RoughnessName(Roughness kind) {
  switch (kind) {
    case Roughness::kGaussian:
      return "gaussian";
    case Roughness::kSavitzkyGolay:
      return "savitzky-golay";
    case Roughness::kSavitzkyGolayMedian:
      return "savitzky-golay-median";
  }
  return "?";
}

Roughness RoughnessNamed(const std::string& name) {
  for (Roughness kind :
       {Roughness::kGaussian, Roughness::kSavitzkyGolay, Roughness::kSavitzkyGolayMedian}) {
    if (RoughnessName(kind) == name) return kind;
  }
  throw std::invalid_argument(
      "expected gaussian, savitzky-golay or savitzky-golay-median, found '" + name + "'");
}

std::vector<double> InputRoughnessCm(const std::vector<float>& input, int joints, int half,
                                     Roughness kind) {
  const std::vector<float> smooth = kind == Roughness::kGaussian
                                        ? GaussianSmooth(input, joints, 1.0)
                                        : SavitzkyGolay(input, joints, 3, 3);
  return LocalCorrectionCm(input, smooth, joints, half, kind == Roughness::kSavitzkyGolayMedian);
}

std::vector<float> SmoothWhereNoisy(const std::vector<float>& motion,
                                    const std::vector<double>& roughness_cm, int joints,
                                    double sigma) {
  if (!(sigma > 0)) return motion;
  const std::vector<float> smooth = GaussianSmooth(motion, joints, sigma);
  const size_t F = 3 * static_cast<size_t>(joints);
  std::vector<float> out = motion;
  for (size_t t = 0; t < roughness_cm.size(); ++t) {
    const double v =
        std::clamp((roughness_cm[t] - kSmoothFromCm) / (kSmoothFullCm - kSmoothFromCm), 0.0, 1.0);
    for (size_t k = t * F; k < (t + 1) * F; ++k)
      out[k] = static_cast<float>(out[k] + v * (smooth[k] - out[k]));
  }
  return out;
}

std::vector<float> BlendRefined(const std::vector<float>& input, const std::vector<float>& refined,
                                int joints, const RefinerBlend& blend) {
  if (blend.weights.empty()) return refined;
  if (blend.weights.size() != static_cast<size_t>(kRefinerBlendBins)) {
    throw std::invalid_argument("refiner_blend: expected " + std::to_string(kRefinerBlendBins) +
                                " weights, got " + std::to_string(blend.weights.size()));
  }
  if (refined.size() != input.size())
    throw std::invalid_argument(
        "refiner_blend: the refined motion's size differs from the input's");
  const std::vector<double> size = InputRoughnessCm(input, joints, 15, blend.roughness);
  const std::vector<float> base = SmoothWhereNoisy(input, size, joints, blend.sigma);
  const size_t F = 3 * static_cast<size_t>(joints);
  std::vector<float> out(input.size());
  for (size_t t = 0; t < size.size(); ++t) {
    const double w = blend.weights[RefinerBlendBin(size[t])];
    for (size_t k = t * F; k < (t + 1) * F; ++k)
      out[k] = static_cast<float>(base[k] + w * (refined[k] - base[k]));
  }
  return blend.accel_bound > 0 ? SmoothToAcceleration(out, size, joints, blend.accel_bound)
                               : SmoothWhereNoisy(out, size, joints, blend.smooth);
}

std::vector<float> SmoothToAcceleration(const std::vector<float>& motion,
                                        const std::vector<double>& roughness_cm, int joints,
                                        double bound) {
  if (std::none_of(roughness_cm.begin(), roughness_cm.end(),
                   [](double r) { return r > kSmoothFromCm; }))
    return motion;  // nowhere smoothed
  const double limit =
      bound * MeanAcceleration(GaussianSmooth(motion, joints, kAccelReferenceSigma), joints, 1.0);
  std::vector<float> out;
  for (double sigma : kOutputSmoothings) {
    out = SmoothWhereNoisy(motion, roughness_cm, joints, sigma);
    if (MeanAcceleration(out, joints, 1.0) <= limit) break;
  }
  return out;
}

RefinerBlendFit::RefinerBlendFit(double sigma, Roughness roughness)
    : sigma_(sigma),
      roughness_(roughness),
      ee_(kRefinerBlendBins, 0.0),
      ce_(kRefinerBlendBins, 0.0),
      cc_(kRefinerBlendBins, 0.0) {}

void RefinerBlendFit::AddSetting(const std::vector<std::vector<float>>& inputs,
                                 const std::vector<std::vector<float>>& refined,
                                 const std::vector<std::vector<float>>& clean, int joints) {
  std::vector<double> ee(kRefinerBlendBins, 0.0), ce = ee, cc = ee;
  double values = 0;
  const size_t F = 3 * static_cast<size_t>(joints);
  for (size_t m = 0; m < inputs.size(); ++m) {
    const std::vector<double> size = InputRoughnessCm(inputs[m], joints, 15, roughness_);
    const std::vector<float> base = SmoothWhereNoisy(inputs[m], size, joints, sigma_);
    for (size_t t = 0; t < size.size(); ++t) {
      const int bin = RefinerBlendBin(size[t]);
      for (size_t k = t * F; k < (t + 1) * F; ++k) {
        const double c = refined[m][k] - base[k], e = clean[m][k] - base[k];
        ee[bin] += e * e;
        ce[bin] += c * e;
        cc[bin] += c * c;
      }
    }
    values += static_cast<double>(inputs[m].size());
  }
  if (values == 0) return;
  for (int b = 0; b < kRefinerBlendBins; ++b) {
    ee_[b] += ee[b] / values;
    ce_[b] += ce[b] / values;
    cc_[b] += cc[b] / values;
  }
}

RefinerBlend RefinerBlendFit::Blend() const {
  RefinerBlend blend;
  blend.sigma = sigma_;
  blend.weights.assign(kRefinerBlendBins, 1.0);
  blend.roughness = roughness_;
  for (int b = 0; b < kRefinerBlendBins; ++b)
    if (cc_[b] > 0) blend.weights[b] = std::clamp(ce_[b] / cc_[b], 0.0, 1.0);
  return blend;
}

double RefinerBlendFit::Error() const {
  const std::vector<double> w = Blend().weights;
  double error = 0;
  for (int b = 0; b < kRefinerBlendBins; ++b)
    error += ee_[b] - 2 * w[b] * ce_[b] + w[b] * w[b] * cc_[b];
  return error;
}

}  // namespace motionfork
