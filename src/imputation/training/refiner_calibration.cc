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
#include "imputation/bone_lengths.h"
#include "imputation/gap_imputation.h"
#include "imputation/motion_imputation.h"
#include "imputation/refiner_fills.h"

namespace motionfork {

namespace {

// Per setting and bucket: sums over the missing values of the products of e, c and l, where e is
// the spline's error (clean - spline), c the refiner's correction (refined - spline) and l the
// local polynomial's (local - spline).
enum Product { kEE, kCE, kCC, kLE, kLL, kCL, kProducts };
struct Sums {
  std::array<double, kProducts> v{};
};
using SettingSums = std::vector<Sums>;  // [kRefinerGapBuckets]

// Squared error of spline + a c + b l over one bucket's sums.
double Squares(const Sums& s, double a, double b) {
  const auto& v = s.v;
  return v[kEE] - 2 * a * v[kCE] - 2 * b * v[kLE] + a * a * v[kCC] + b * b * v[kLL] +
         2 * a * b * v[kCL];
}

// Over a setting's buckets with weights a, b per bucket.
double SettingSquares(const SettingSums& s, const std::vector<double>& a,
                      const std::vector<double>& b) {
  double total = 0;
  for (int k = 0; k < kRefinerGapBuckets; ++k) total += Squares(s[k], a[k], b[k]);
  return total;
}

// The (a, b) in [0, 1]^2 minimising Squares(s, a, b): the unconstrained minimum when inside, else
// the best of each edge's minimum and the corners.
std::pair<double, double> BestWeights(const Sums& s) {
  const auto& v = s.v;
  std::vector<std::pair<double, double>> candidates = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  const double det = v[kCC] * v[kLL] - v[kCL] * v[kCL];
  if (det > 1e-12 * std::max(1e-300, v[kCC] * v[kLL])) {
    candidates.push_back(
        {(v[kCE] * v[kLL] - v[kLE] * v[kCL]) / det, (v[kLE] * v[kCC] - v[kCE] * v[kCL]) / det});
  }
  for (double fixed : {0.0, 1.0}) {  // one weight on an edge, the other at its best
    if (v[kCC] > 0) candidates.push_back({(v[kCE] - fixed * v[kCL]) / v[kCC], fixed});
    if (v[kLL] > 0) candidates.push_back({fixed, (v[kLE] - fixed * v[kCL]) / v[kLL]});
  }
  std::pair<double, double> best{0, 0};
  for (auto [a, b] : candidates) {
    if (!(a >= 0 && a <= 1 && b >= 0 && b <= 1)) continue;
    if (Squares(s, a, b) < Squares(s, best.first, best.second)) best = {a, b};
  }
  return best;
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
  RefinerCalibration out;
  out.clips = static_cast<int>(clips.size());
  out.bucket_values.assign(kRefinerGapBuckets, 0);
  // Every clip with every setting's mask: fill(setting, clean clip, fills, uncalibrated refined).
  auto for_each_fill = [&](const std::string& stage, const auto& fill) {
    for (size_t c = 0; c < clips.size(); ++c) {
      const std::vector<float>& clean = clips[c];
      const int T = static_cast<int>(clean.size() / N);
      std::vector<float> positions(static_cast<size_t>(T) * J * 3, 0.0f);  // root at the origin
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
        fill(s, clean, f, model.Refine(f, /*calibrated=*/false));
      }
      ReportProgress(progress, stage,
                     static_cast<double>(c + 1) / static_cast<double>(clips.size()));
    }
  };
  std::vector<SettingSums> sums(settings.size(), SettingSums(kRefinerGapBuckets));
  std::vector<int64_t> values(settings.size(), 0);
  for_each_fill("calibrating on held-out clips",
                [&](size_t s, const std::vector<float>& clean, const RefinerFills& f,
                    const std::vector<float>& refined) {
                  const std::vector<int> buckets = RefinerGapBuckets(f);
                  for (size_t i = 0; i < buckets.size(); ++i) {
                    if (buckets[i] < 0) continue;
                    const double e = clean[i] - f.spline[i], c = refined[i] - f.spline[i],
                                 l = f.local[i] - f.spline[i];
                    auto& v = sums[s][buckets[i]].v;
                    v[kEE] += e * e;
                    v[kCE] += c * e;
                    v[kCC] += c * c;
                    v[kLE] += l * e;
                    v[kLL] += l * l;
                    v[kCL] += c * l;
                    ++values[s];
                    ++out.bucket_values[buckets[i]];
                  }
                });
  // Minimise the sum over settings of (calibrated squares / spline squares): each bucket on its
  // own, over its sums divided by their setting's spline squares.
  out.blend.refiner.assign(kRefinerGapBuckets, 1.0);
  out.blend.local.assign(kRefinerGapBuckets, 0.0);
  std::vector<double> spline(settings.size(), 0.0);
  for (size_t s = 0; s < settings.size(); ++s)
    for (const Sums& x : sums[s]) spline[s] += x.v[kEE];
  for (int k = 0; k < kRefinerGapBuckets; ++k) {
    Sums pooled;
    for (size_t s = 0; s < settings.size(); ++s) {
      if (!(spline[s] > 0)) continue;
      for (int p = 0; p < kProducts; ++p) pooled.v[p] += sums[s][k].v[p] / spline[s];
    }
    if (pooled.v[kCC] > 0 || pooled.v[kLL] > 0)
      std::tie(out.blend.refiner[k], out.blend.local[k]) = BestWeights(pooled);
  }
  // The same with the rigid bones kept at their observed lengths: kept when that lowers the sum.
  ImputationBlend with_bones = out.blend;
  with_bones.keep_bones = true;
  std::vector<double> kept(settings.size(), 0.0);
  for_each_fill("keeping bone lengths on held-out clips",
                [&](size_t s, const std::vector<float>& clean, const RefinerFills& f,
                    const std::vector<float>& refined) {
                  const std::vector<float> k = BlendRefinerFills(skeleton, f, refined, with_bones);
                  for (size_t i = 0; i < k.size(); ++i)
                    if (f.mask[i]) kept[s] += std::pow(double(k[i]) - clean[i], 2);
                });
  const std::vector<double> ones(kRefinerGapBuckets, 1.0), zeros(kRefinerGapBuckets, 0.0);
  double calibrated_sum = 0, kept_sum = 0;
  for (size_t s = 0; s < settings.size(); ++s) {
    if (values[s] == 0) continue;
    auto rms = [&](double squares) { return 100 * std::sqrt(std::max(0.0, squares) / values[s]); };
    const double calibrated = SettingSquares(sums[s], out.blend.refiner, out.blend.local);
    out.settings.push_back({settings[s].name, values[s], rms(spline[s]),
                            rms(SettingSquares(sums[s], ones, zeros)), rms(calibrated),
                            rms(kept[s])});
    if (spline[s] > 0) {
      calibrated_sum += calibrated / spline[s];
      kept_sum += kept[s] / spline[s];
    }
  }
  if (out.settings.empty())
    throw std::invalid_argument("calibrate: no clip is long enough for any gap setting");
  out.blend.keep_bones = kept_sum < calibrated_sum;
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
  m.refiner_weights = c.blend.refiner;
  m.refiner_local_weights = c.blend.local;
  m.refiner_keep_bones = c.blend.keep_bones;
  SetManifestInfo(&m.info, "refiner_calibration",
                  std::to_string(c.clips) + " held-out clips, seed " + std::to_string(seed));
  SaveHgvaeBundle(out_dir, m, net);
  return c;
}

std::string RefinerCalibrationText(const RefinerCalibration& c, const std::string& out) {
  std::string text = StringPrintf("refiner calibration on %d held-out clips\n%-28s %8s %8s %12s\n",
                                  c.clips, "bucket", "refiner", "local", "values");
  for (int b = 0; b < kRefinerGapBuckets; ++b) {
    StringAppendf(&text, "%-28s %8.3f %8.3f %12s\n", RefinerGapBucketName(b).c_str(),
                  c.blend.refiner[b], c.blend.local[b], WithThousands(c.bucket_values[b]).c_str());
  }
  StringAppendf(&text, "keep bone lengths: %s\n", c.blend.keep_bones ? "yes" : "no");
  StringAppendf(&text, "\nRMS of the missing values (cm)\n%-28s %10s %8s %8s %10s %8s\n", "setting",
                "values", "spline", "refiner", "calibrated", "bones");
  for (const RefinerCalibration::Setting& s : c.settings) {
    StringAppendf(&text, "%-28s %10s %8.3f %8.3f %10.3f %8.3f\n", s.name.c_str(),
                  WithThousands(s.values).c_str(), s.spline_cm, s.refiner_cm, s.calibrated_cm,
                  s.kept_cm);
  }
  return text + "wrote " + out + "\n";
}

}  // namespace motionfork
