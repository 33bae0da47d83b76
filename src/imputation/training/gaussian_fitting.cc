#include "imputation/training/gaussian_fitting.h"

#include <array>
#include <cmath>
#include <iterator>
#include <stdexcept>

#include "bundle/hgvae_bundle.h"
#include "bundle/manifest.h"
#include "core/text_format.h"
#include "imputation/motion_imputation.h"
#include "imputation/refiner_adaptation.h"
#include "imputation/refiner_fills.h"
#include "imputation/training/smoothing_calibration.h"
#include "io/file_util.h"

namespace motionfork {
namespace {

constexpr const char* kGaussianFile = "window_gaussian.npy";

// 1 where a missing value has no observed value of its coordinate after it or none before it (and
// some observed value of it in the window).
std::vector<uint8_t> OneSided(const std::vector<uint8_t>& mask, size_t coords) {
  const size_t T = mask.size() / coords;
  const std::vector<ObservedSpan> seen = ObservedSpans(mask, coords);
  std::vector<uint8_t> out(mask.size(), 0);
  for (size_t t = 0; t < T; ++t) {
    for (size_t v = 0; v < coords; ++v) {
      const size_t i = t * coords + v;
      out[i] = mask[i] && seen[v].first < T && (t < seen[v].first || t > seen[v].last);
    }
  }
  return out;
}

// The Gaussian as the bundle stores it (float32), so that it is scored as it will be used.
WindowGaussian RoundedToFloat(WindowGaussian g) {
  for (double& x : g.mean) x = static_cast<float>(x);
  for (double& x : g.cov) x = static_cast<float>(x);
  return g;
}

}  // namespace

GaussianFit FitGaussian(const HgvaeModel& model, const std::vector<std::vector<float>>& train,
                        const std::vector<std::vector<float>>& held_out, uint64_t seed,
                        const StageProgress& progress) {
  if (!model.has_refiner())
    throw std::invalid_argument("fit-gaussian: expected an HG-VAE bundle with a refiner");
  const Skeleton& skeleton = model.skeleton();
  const int W = model.window(), N = 3 * (skeleton.num_joints() - 1);
  GaussianFit out;
  out.training_clips = static_cast<int>(train.size());
  out.held_out_clips = static_cast<int>(held_out.size());
  ReportProgress(progress, "window Gaussian on training clips", 0.0);
  out.gaussian = RoundedToFloat(FitWindowGaussian(train, W, N));
  ReportProgress(progress, "window Gaussian on training clips", 1.0);
  ImputationBlend blend = model.calibrated_blend();
  blend.gaussian = nullptr;  // the bundle's fill without a Gaussian it may hold already
  const RawRefiner raw = [&model](const RefinerFills& f) { return model.Refine(f, false); };
  const std::vector<float> fallback = TrainingMeanPose(model);
  const std::vector<HeldOutHistory> histories =
      HeldOutHistories(held_out, W, N, seed, &out.histories);
  if (histories.empty()) {
    throw std::invalid_argument(
        "fit-gaussian: no held-out clip holds a window of the model's length");
  }
  const size_t shares = std::size(kSmoothingShares);
  out.shares.resize(shares);
  // Squares per share and fill (the bundle's, then each scope): all, one-sided, last frame.
  std::vector<std::array<std::array<double, 3>, 3>> sq(shares);
  for (auto& s : sq)
    for (auto& f : s) f = {0, 0, 0};
  for (size_t s = 0; s < shares; ++s) out.shares[s].share = kSmoothingShares[s];
  for (size_t h = 0; h < histories.size(); ++h) {
    const HeldOutHistory& it = histories[h];
    const RefinerFills f = MakeRefinerFills(skeleton, WithRootAtOrigin(it.clean.data(), W, N),
                                            WithRootAtOrigin(it.mask.data(), W, N), fallback);
    const std::vector<float> bundle =
        BlendRefinerFills(skeleton, f, raw(f), AdaptToMotion(skeleton, f, raw, blend));
    const std::vector<float> fills[3] = {
        bundle, FillFromWindowGaussian(out.gaussian, bundle, f.mask, kGaussianScopes[0]),
        FillFromWindowGaussian(out.gaussian, bundle, f.mask, kGaussianScopes[1])};
    const std::vector<uint8_t> one = OneSided(f.mask, N);
    GaussianFit::Share& sh = out.shares[it.share];
    for (size_t i = 0; i < f.mask.size(); ++i) {
      if (!f.mask[i]) continue;
      const bool last = i >= static_cast<size_t>((W - 1) * N);
      ++sh.values;
      sh.one_sided += one[i];
      sh.last += last;
      for (int k = 0; k < 3; ++k) {
        const double e = std::pow(double(fills[k][i]) - it.clean[i], 2);
        sq[it.share][k][0] += e;
        if (one[i]) sq[it.share][k][1] += e;
        if (last) sq[it.share][k][2] += e;
      }
    }
    ReportProgress(progress, "held-out histories", double(h + 1) / histories.size());
  }
  auto rms_cm = [](double s, long long n) { return n > 0 ? 100 * std::sqrt(s / n) : 0.0; };
  for (size_t s = 0; s < shares; ++s) {
    GaussianFit::Share& sh = out.shares[s];
    for (int k = 0; k < 3; ++k) {
      sh.all_cm[k] = rms_cm(sq[s][k][0], sh.values);
      sh.one_sided_cm[k] = rms_cm(sq[s][k][1], sh.one_sided);
      sh.last_cm[k] = rms_cm(sq[s][k][2], sh.last);
    }
    for (int k = 0; k < 2; ++k)
      out.score[k] += sq[s][0][0] > 0 ? sq[s][k + 1][0] / sq[s][0][0] : 1.0;
  }
  const int best = out.score[1] < out.score[0] ? 1 : 0;
  out.scope = kGaussianScopes[best];
  out.chosen = out.score[best] < static_cast<double>(shares);
  return out;
}

GaussianFit FitGaussianIntoBundle(const std::string& model_dir,
                                  const std::vector<std::vector<float>>& train,
                                  const std::vector<std::vector<float>>& held_out, uint64_t seed,
                                  const std::string& out_dir, const StageProgress& progress) {
  RequireSeparateFolder("fit-gaussian", out_dir, model_dir);
  HgvaeManifest m;
  HgvaeNet net = LoadHgvaeBundle(model_dir, &m);  // saved as loaded: the same weights file
  const GaussianFit fit = FitGaussian(LoadHgvaeModel(model_dir), train, held_out, seed, progress);
  if (fit.chosen) {
    m.refiner_gaussian = {
        kGaussianFile,       fit.gaussian.frames,
        fit.gaussian.coords, fit.gaussian.windows,
        fit.scope,           std::make_shared<const WindowGaussian>(fit.gaussian)};
    SetManifestInfo(&m.info, "refiner_gaussian",
                    std::to_string(fit.training_clips) + " training clips; chosen on " +
                        std::to_string(fit.held_out_clips) + " held-out clips, seed " +
                        std::to_string(seed));
  }
  SaveHgvaeBundle(out_dir, m, net);
  return fit;
}

std::string GaussianFitText(const GaussianFit& fit, const std::string& out) {
  std::string text = StringPrintf(
      "window Gaussian: %d frames x %d coordinates, %s windows of %d training clips\n"
      "%d histories of %d frames per share from %d held-out clips, filled over the history alone; "
      "RMS (cm) of the bundle's fill / with the Gaussian for the one-sided values / for every "
      "value\n"
      "%-8s %9s %26s %9s %26s %9s %26s\n",
      fit.gaussian.frames, fit.gaussian.coords, WithThousands(fit.gaussian.windows).c_str(),
      fit.training_clips, fit.histories, fit.gaussian.frames, fit.held_out_clips, "missing",
      "values", "all", "one-sided", "one-sided values", "last", "last frame");
  for (const GaussianFit::Share& s : fit.shares) {
    auto three = [](const double* x) {
      return StringPrintf("%.3f / %.3f / %.3f", x[0], x[1], x[2]);
    };
    StringAppendf(&text, "%-8s %9s %26s %9s %26s %9s %26s\n",
                  StringPrintf("%g%%", 100 * s.share).c_str(), WithThousands(s.values).c_str(),
                  three(s.all_cm).c_str(), WithThousands(s.one_sided).c_str(),
                  three(s.one_sided_cm).c_str(), WithThousands(s.last).c_str(),
                  three(s.last_cm).c_str());
  }
  StringAppendf(&text,
                "summed squares / the bundle fill's, of %zu: one-sided %.3f, every value %.3f: %s\n"
                "wrote %s\n",
                fit.shares.size(), fit.score[0], fit.score[1],
                fit.chosen ? StringPrintf("the Gaussian fills %s (refiner_gaussian)",
                                          fit.scope == GaussianScope::kOneSided
                                              ? "the one-sided values"
                                              : "every value of a short motion")
                                 .c_str()
                           : "not taken (the bundle as it was)",
                out.c_str());
  return text;
}

}  // namespace motionfork
