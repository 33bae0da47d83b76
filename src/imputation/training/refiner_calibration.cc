#include "imputation/training/refiner_calibration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "bundle/hgvae_bundle.h"
#include "bundle/manifest.h"
#include "core/parallel_for.h"
#include "core/text_format.h"
#include "imputation/gap_imputation.h"
#include "imputation/motion_imputation.h"
#include "imputation/refiner_fills.h"

namespace motionfork {

namespace {

// Per setting and bucket: sums over the missing values of e^2, c e and c^2, where e is the
// spline's error (clean - spline) and c the refiner's correction (refined - spline).
struct Sums {
  std::array<double, 3> v{0, 0, 0};
};
using SettingSums = std::vector<Sums>;  // [kRefinerGapBuckets]

// Squared error of spline + w c summed over a setting's buckets.
double CalibratedSquares(const SettingSums& s, const std::vector<double>& w) {
  double total = 0;
  for (int b = 0; b < kRefinerGapBuckets; ++b)
    total += s[b].v[0] - 2 * w[b] * s[b].v[1] + w[b] * w[b] * s[b].v[2];
  return total;
}

}  // namespace

RefinerCalibration CalibrateRefiner(const HgvaeModel& model,
                                    const std::vector<std::vector<float>>& clips, uint64_t seed,
                                    const StageProgress& progress) {
  if (!model.has_refiner())
    throw std::invalid_argument("calibrate: the bundle has no refiner (motionfork hgvae refine)");
  const Skeleton& skeleton = model.skeleton();
  const int J = skeleton.num_joints(), N = 3 * (J - 1);
  const std::vector<GapSetting> settings = StandardGapSettings(skeleton, model.manifest().fps);
  const std::vector<float> fallback = TrainingMeanPose(model);
  std::vector<SettingSums> sums(settings.size(), SettingSums(kRefinerGapBuckets));
  std::vector<int64_t> values(settings.size(), 0);
  RefinerCalibration out;
  out.bucket_values.assign(kRefinerGapBuckets, 0);
  for (size_t c = 0; c < clips.size(); ++c) {
    const std::vector<float>& clean = clips[c];
    const int T = static_cast<int>(clean.size() / N);
    std::vector<float> positions(static_cast<size_t>(T) * J * 3, 0.0f);  // the root at the origin
    for (int t = 0; t < T; ++t) {
      std::copy(clean.begin() + static_cast<size_t>(t) * N,
                clean.begin() + static_cast<size_t>(t + 1) * N,
                positions.begin() + static_cast<size_t>(t) * J * 3 + 3);
    }
    for (size_t s = 0; s < settings.size(); ++s) {
      const std::vector<uint8_t> mask =
          GapMask(settings[s], T, J, ItemSeed(seed, static_cast<int>(s * 100003 + c)));
      if (std::count(mask.begin(), mask.end(), 1) == 0) continue;
      const RefinerFills f = MakeRefinerFills(skeleton, positions, mask, fallback);
      const std::vector<float> refined = model.Refine(f, /*calibrated=*/false);
      const std::vector<int> buckets = RefinerGapBuckets(f);
      for (size_t i = 0; i < buckets.size(); ++i) {
        if (buckets[i] < 0) continue;
        const double e = clean[i] - f.spline[i], corr = refined[i] - f.spline[i];
        std::array<double, 3>& v = sums[s][buckets[i]].v;
        v[0] += e * e;
        v[1] += corr * e;
        v[2] += corr * corr;
        ++values[s];
        ++out.bucket_values[buckets[i]];
      }
    }
    ++out.clips;
    ReportProgress(progress, "calibrating on held-out clips",
                   static_cast<double>(c + 1) / static_cast<double>(clips.size()));
  }
  // Minimise the sum over settings of (calibrated squares / spline squares): per bucket
  // w = sum_s (ce)_sb / E_s over sum_s (cc)_sb / E_s.
  out.weights.assign(kRefinerGapBuckets, 1.0);
  for (int b = 0; b < kRefinerGapBuckets; ++b) {
    double num = 0, den = 0;
    for (size_t s = 0; s < settings.size(); ++s) {
      double spline = 0;
      for (const Sums& x : sums[s]) spline += x.v[0];
      if (!(spline > 0)) continue;
      num += sums[s][b].v[1] / spline;
      den += sums[s][b].v[2] / spline;
    }
    if (den > 0) out.weights[b] = std::clamp(num / den, 0.0, 1.0);
  }
  const std::vector<double> ones(kRefinerGapBuckets, 1.0), zeros(kRefinerGapBuckets, 0.0);
  for (size_t s = 0; s < settings.size(); ++s) {
    if (values[s] == 0) continue;
    auto rms = [&](const std::vector<double>& w) {
      return 100 * std::sqrt(std::max(0.0, CalibratedSquares(sums[s], w)) / values[s]);
    };
    out.settings.push_back({settings[s].name, values[s], rms(zeros), rms(ones), rms(out.weights)});
  }
  if (out.settings.empty())
    throw std::invalid_argument("calibrate: no clip is long enough for any gap setting");
  return out;
}

RefinerCalibration CalibrateHgvaeBundle(const std::string& model_dir,
                                        const std::vector<std::vector<float>>& clips, uint64_t seed,
                                        const std::string& out_dir, const StageProgress& progress) {
  namespace fs = std::filesystem;
  if (fs::exists(out_dir) && fs::exists(model_dir) && fs::equivalent(out_dir, model_dir)) {
    throw std::invalid_argument("calibrate: --out " + out_dir +
                                " is the input bundle; expected another folder");
  }
  HgvaeManifest m;
  HgvaeNet net = LoadHgvaeBundle(model_dir, &m);  // saved as loaded: the same weights file
  const RefinerCalibration c = CalibrateRefiner(LoadHgvaeModel(model_dir), clips, seed, progress);
  m.refiner_weights = c.weights;
  SetManifestInfo(&m.info, "refiner_calibration",
                  std::to_string(c.clips) + " held-out clips, seed " + std::to_string(seed));
  SaveHgvaeBundle(out_dir, m, net);
  return c;
}

std::string RefinerCalibrationText(const RefinerCalibration& c, const std::string& out) {
  std::string text = StringPrintf("refiner calibration on %d held-out clips\n%-30s %7s %12s\n",
                                  c.clips, "bucket", "weight", "values");
  for (int b = 0; b < kRefinerGapBuckets; ++b) {
    StringAppendf(&text, "%-30s %7.3f %12s\n", RefinerGapBucketName(b).c_str(), c.weights[b],
                  WithThousands(c.bucket_values[b]).c_str());
  }
  StringAppendf(&text, "\nRMS of the missing values (cm)\n%-28s %10s %8s %8s %10s\n", "setting",
                "values", "spline", "refiner", "calibrated");
  for (const RefinerCalibration::Setting& s : c.settings) {
    StringAppendf(&text, "%-28s %10s %8.3f %8.3f %10.3f\n", s.name.c_str(),
                  WithThousands(s.values).c_str(), s.spline_cm, s.refiner_cm, s.calibrated_cm);
  }
  return text + "wrote " + out + "\n";
}

}  // namespace motionfork
