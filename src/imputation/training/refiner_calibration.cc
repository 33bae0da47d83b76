#include "imputation/training/refiner_calibration.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <tuple>

#include "bundle/hgvae_bundle.h"
#include "bundle/manifest.h"
#include "core/parallel_for.h"
#include "core/text_format.h"
#include "imputation/blend_fit.h"
#include "imputation/bone_lengths.h"
#include "imputation/gap_imputation.h"
#include "imputation/motion_imputation.h"
#include "imputation/refiner_adaptation.h"
#include "imputation/refiner_fills.h"
#include "io/file_util.h"

namespace motionfork {

namespace {

// One clip under one setting's mask: per bucket the sums of its missing values and of its probes'
// hidden values (refiner_adaptation.h).
struct Item {
  size_t clip = 0, setting = 0;
  BucketSums real, probes;
};

// Per bucket the weights minimising the sum over settings of (calibrated squares / spline
// squares) over the items `use` takes: each bucket on its own, over its sums divided by their
// setting's spline squares.
template <typename Use>
ImputationBlend FitBlend(const std::vector<Item>& items, size_t settings, const Use& use) {
  std::vector<double> spline(settings, 0.0);
  for (const Item& it : items)
    if (use(it))
      for (const BlendSums& x : it.real) spline[it.setting] += x.v[BlendSums::kEE];
  BucketSums pooled(kRefinerGapBuckets);
  for (const Item& it : items) {
    if (!use(it) || !(spline[it.setting] > 0)) continue;
    for (int k = 0; k < kRefinerGapBuckets; ++k)
      pooled[k] += it.real[k].Scaled(1.0 / spline[it.setting]);
  }
  ImputationBlend blend;
  blend.refiner.assign(kRefinerGapBuckets, 1.0);
  blend.local.assign(kRefinerGapBuckets, 0.0);
  for (int k = 0; k < kRefinerGapBuckets; ++k) {
    const auto& v = pooled[k].v;
    if (v[BlendSums::kCC] > 0 || v[BlendSums::kLL] > 0)
      std::tie(blend.refiner[k], blend.local[k]) = BestBlendWeights(pooled[k]);
  }
  return blend;
}

// The blend an item's motion gets: adapted to its probes where adapt_values says so.
ImputationBlend ItemBlend(const ImputationBlend& blend, const Item& it) {
  return AdaptsToMotion(blend) ? AdaptBlend(blend, it.probes) : blend;
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
  const RawRefiner raw = [&model](const RefinerFills& f) { return model.Refine(f, false); };
  RefinerCalibration out;
  out.clips = static_cast<int>(clips.size());
  out.bucket_values.assign(kRefinerGapBuckets, 0);
  // Every clip with every setting's mask, in the same order each time:
  // fill(clip, setting, clean clip, fills, uncalibrated refined).
  auto for_each_fill = [&](const std::string& stage, const auto& fill) {
    for (size_t c = 0; c < clips.size(); ++c) {
      const std::vector<float>& clean = clips[c];
      const int T = static_cast<int>(clean.size() / N);
      const std::vector<float> positions = WithRootAtOrigin(clean.data(), T, N);
      for (size_t s = 0; s < settings.size(); ++s) {
        const std::vector<uint8_t> mask =
            GapMask(settings[s], T, J, ItemSeed(seed, static_cast<int>(s * 100003 + c)));
        if (std::count(mask.begin(), mask.end(), 1) == 0) continue;
        const RefinerFills f = MakeRefinerFills(skeleton, positions, mask, fallback);
        fill(c, s, clean, f, raw(f));
      }
      ReportProgress(progress, stage,
                     static_cast<double>(c + 1) / static_cast<double>(clips.size()));
    }
  };
  std::vector<Item> items;
  std::vector<int64_t> values(settings.size(), 0);
  for_each_fill("calibrating on held-out clips",
                [&](size_t c, size_t s, const std::vector<float>& clean, const RefinerFills& f,
                    const std::vector<float>& refined) {
                  Item it{c, s, BucketSums(kRefinerGapBuckets),
                          ProbeBlendSums(FillRefinerProbes(skeleton, f, raw), f)};
                  AddBlendSums(f, refined, clean, f.mask, &it.real);
                  for (int k = 0; k < kRefinerGapBuckets; ++k) {
                    values[s] += it.real[k].values;
                    out.bucket_values[k] += it.real[k].values;
                  }
                  items.push_back(std::move(it));
                });
  std::vector<double> spline(settings.size(), 0.0);
  for (const Item& it : items)
    for (const BlendSums& x : it.real) spline[it.setting] += x.v[BlendSums::kEE];
  // Sum over settings of squares / spline squares, with the blend each item gets from blend_of.
  auto relative = [&](const auto& blend_of, std::vector<double>* per_setting) {
    std::vector<double> squares(settings.size(), 0.0);
    for (const Item& it : items) {
      const ImputationBlend b = blend_of(it);
      squares[it.setting] += BlendSquares(it.real, b.refiner, b.local);
    }
    double total = 0;
    for (size_t s = 0; s < settings.size(); ++s)
      if (spline[s] > 0) total += squares[s] / spline[s];
    if (per_setting) *per_setting = squares;
    return total;
  };
  out.blend = FitBlend(items, settings.size(), [](const Item&) { return true; });
  // How much to adapt to each motion, cross-fitted: the weights fitted on one half of the clips,
  // adapted on the other half with each prior, scored there per gap length class; each class
  // takes its lowest (ties: the prior best over all classes).
  const ImputationBlend halves[2] = {
      FitBlend(items, settings.size(), [](const Item& it) { return it.clip % 2 == 1; }),
      FitBlend(items, settings.size(), [](const Item& it) { return it.clip % 2 == 0; })};
  const int per_length = kRefinerGapBuckets / kRefinerGapLengths;
  std::vector<std::vector<double>> length_scores;  // [prior][length class]
  for (const double prior : kAdaptPriors) {
    std::vector<double> scores(kRefinerGapLengths, 0.0);
    for (const Item& it : items) {
      if (!(spline[it.setting] > 0)) continue;
      ImputationBlend b = halves[it.clip % 2];
      b.adapt_values = {prior};
      b = ItemBlend(b, it);
      for (int k = 0; k < kRefinerGapBuckets; ++k)
        scores[k / per_length] +=
            BlendSquares(it.real[k], b.refiner[k], b.local[k]) / spline[it.setting];
    }
    double total = 0;
    for (double s : scores) total += s;
    out.adapt_scores.push_back({prior, total});
    length_scores.push_back(std::move(scores));
  }
  const size_t best = static_cast<size_t>(
      std::min_element(out.adapt_scores.begin(), out.adapt_scores.end(),
                       [](const auto& x, const auto& y) { return x.second < y.second; }) -
      out.adapt_scores.begin());
  for (int c = 0; c < kRefinerGapLengths; ++c) {
    size_t pick = best;
    for (size_t p = 0; p < length_scores.size(); ++p)
      if (length_scores[p][c] < length_scores[pick][c]) pick = p;
    out.length_priors.push_back(kAdaptPriors[pick]);
    out.length_score += length_scores[pick][c];
  }
  out.blend.adapt_values = out.length_priors;
  if (std::adjacent_find(out.length_priors.begin(), out.length_priors.end(),
                         std::not_equal_to<double>()) == out.length_priors.end())
    out.blend.adapt_values = {out.length_priors[0]};  // one for all
  if (!AdaptsToMotion(out.blend)) out.blend.adapt_values.clear();
  // The rigid bones kept at their observed lengths: kept when that lowers the sum.
  ImputationBlend with_bones = out.blend;
  with_bones.keep_bones = true;
  std::vector<double> kept(settings.size(), 0.0);
  for_each_fill("keeping bone lengths on held-out clips",
                [&](size_t, size_t s, const std::vector<float>& clean, const RefinerFills& f,
                    const std::vector<float>& refined) {
                  const std::vector<float> k = BlendRefinerFills(
                      skeleton, f, refined, AdaptToMotion(skeleton, f, raw, with_bones));
                  for (size_t i = 0; i < k.size(); ++i)
                    if (f.mask[i]) kept[s] += std::pow(double(k[i]) - clean[i], 2);
                });
  std::vector<double> raw_squares, calibrated, adapted;
  ImputationBlend as_is = out.blend, ones;
  as_is.adapt_values.clear();
  ones.refiner.assign(kRefinerGapBuckets, 1.0);
  ones.local.assign(kRefinerGapBuckets, 0.0);
  relative([&](const Item&) { return ones; }, &raw_squares);
  relative([&](const Item&) { return as_is; }, &calibrated);
  const double adapted_sum =
      relative([&](const Item& it) { return ItemBlend(out.blend, it); }, &adapted);
  double kept_sum = 0;
  for (size_t s = 0; s < settings.size(); ++s) {
    if (values[s] == 0) continue;
    auto rms = [&](double squares) { return 100 * std::sqrt(std::max(0.0, squares) / values[s]); };
    out.settings.push_back({settings[s].name, values[s], rms(spline[s]), rms(raw_squares[s]),
                            rms(calibrated[s]), rms(adapted[s]), rms(kept[s])});
    if (spline[s] > 0) kept_sum += kept[s] / spline[s];
  }
  if (out.settings.empty())
    throw std::invalid_argument("calibrate: no clip is long enough for any gap setting");
  out.blend.keep_bones = kept_sum < adapted_sum;
  out.smoothing = CalibrateSmoothing(model, out.blend, clips, seed + 13, progress);
  out.blend.smoothing = out.smoothing.chosen;
  return out;
}

RefinerCalibration CalibrateHgvaeBundle(const std::string& model_dir,
                                        const std::vector<std::vector<float>>& clips, uint64_t seed,
                                        const std::string& out_dir, const StageProgress& progress) {
  RequireSeparateFolder("calibrate", out_dir, model_dir);
  HgvaeManifest m;
  HgvaeNet net = LoadHgvaeBundle(model_dir, &m);  // saved as loaded: the same weights file
  const RefinerCalibration c = CalibrateRefiner(LoadHgvaeModel(model_dir), clips, seed, progress);
  m.refiner_weights = c.blend.refiner;
  m.refiner_local_weights = c.blend.local;
  m.refiner_keep_bones = c.blend.keep_bones;
  m.refiner_adapt_values = c.blend.adapt_values;
  m.refiner_smoothing = c.blend.smoothing;
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
  text += "adapting to each motion (cross-fitted sum of squares / spline's over settings):";
  for (const auto& [prior, score] : c.adapt_scores) {
    StringAppendf(&text, " %s %.3f", prior > 0 ? StringPrintf("%g", prior).c_str() : "off", score);
  }
  text += "\nper gap length (1, 2, 3-4, 5-8, 9-16, 17-32, 33+, unbracketed), each its lowest:";
  for (double prior : c.length_priors) StringAppendf(&text, " %g", prior);
  StringAppendf(&text, " (sum %.3f)\n", c.length_score);
  std::string priors;
  for (double prior : c.blend.adapt_values) priors += StringPrintf(" %g", prior);
  StringAppendf(
      &text, "adapt to each motion: %s\n",
      AdaptsToMotion(c.blend) ? ("yes, priors worth" + priors + " values").c_str() : "no");
  StringAppendf(&text, "keep bone lengths: %s\n", c.blend.keep_bones ? "yes" : "no");
  text += "smoothing the filled values, bracketed (whole clips; summed squares / spline's):";
  for (const auto& [lambda, score] : c.smoothing.bracketed)
    StringAppendf(&text, " %g %.3f", lambda, score);
  StringAppendf(&text, "\n  observed on one side only (%d histories of the window per share):",
                c.smoothing.histories);
  for (const auto& [lambda, score] : c.smoothing.one_sided)
    StringAppendf(&text, " %g %.3f", lambda, score);
  StringAppendf(&text, "\nsmooth the filled values: bracketed %g, one-sided %g (0: not)\n",
                c.smoothing.chosen.bracketed, c.smoothing.chosen.one_sided);
  StringAppendf(&text, "\nRMS of the missing values (cm)\n%-28s %10s %8s %8s %10s %8s %8s\n",
                "setting", "values", "spline", "refiner", "calibrated", "adapted", "bones");
  for (const RefinerCalibration::Setting& s : c.settings) {
    StringAppendf(&text, "%-28s %10s %8.3f %8.3f %10.3f %8.3f %8.3f\n", s.name.c_str(),
                  WithThousands(s.values).c_str(), s.spline_cm, s.refiner_cm, s.calibrated_cm,
                  s.adapted_cm, s.kept_cm);
  }
  return text + "wrote " + out + "\n";
}

}  // namespace motionfork
