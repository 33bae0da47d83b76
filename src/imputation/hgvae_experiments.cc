#include "imputation/hgvae_experiments.h"

#include <algorithm>
#include <numeric>
#include <random>
#include <stdexcept>

#include "imputation/occlusion.h"

namespace motionfork {

std::vector<ImputationFigure> ImputationExperiment(const HgvaeModel& model,
                                                   const std::vector<float>& windows,
                                                   const std::vector<Occlusion>& settings,
                                                   const ImputeOptions& options, uint64_t seed,
                                                   const std::function<void(int, int)>& progress) {
  const int T = model.window(), N = model.coords();
  const int count = static_cast<int>(windows.size() / (static_cast<size_t>(T) * N));
  std::vector<ImputationFigure> out;
  for (size_t s = 0; s < settings.size(); ++s) {
    const Occlusion& o = settings[s];
    const std::vector<uint8_t> mask =
        o.share > 0 ? RandomOcclusion(count, T * N, o.share, seed + 1000 * s)
                    : JointOcclusion(count, T, model.skeleton().num_joints(), o.joints);
    std::vector<float> degraded = windows;
    for (size_t i = 0; i < mask.size(); ++i) {
      if (mask[i]) degraded[i] = std::numeric_limits<float>::quiet_NaN();  // nothing leaks
    }
    const std::vector<float> mean_filled = model.MeanImpute(degraded, mask);
    const ImputeResult r = model.Impute(degraded, mask, options);
    ImputationFigure f;
    f.occlusion = o;
    double se_mean = 0, se_model = 0;
    for (size_t i = 0; i < mask.size(); ++i) {
      if (!mask[i]) continue;
      ++f.missing_values;
      se_mean += double(mean_filled[i] - windows[i]) * (mean_filled[i] - windows[i]);
      se_model += double(r.windows[i] - windows[i]) * (r.windows[i] - windows[i]);
    }
    f.mse_mean = se_mean / std::max<int64_t>(1, f.missing_values);
    f.mse_model = se_model / std::max<int64_t>(1, f.missing_values);
    f.reduction = f.mse_mean > 0 ? 1.0 - f.mse_model / f.mse_mean : 0.0;
    f.score_before = std::accumulate(r.score_before.begin(), r.score_before.end(), 0.0) / count;
    f.score_after = std::accumulate(r.score_after.begin(), r.score_after.end(), 0.0) / count;
    out.push_back(f);
    if (progress) progress(static_cast<int>(s + 1), static_cast<int>(settings.size()));
  }
  return out;
}

double Auroc(const std::vector<double>& clean, const std::vector<double>& degraded) {
  if (clean.empty() || degraded.empty())
    throw std::invalid_argument("Auroc: expected scores in both groups");
  // Rank-sum (Mann-Whitney U) with ties counted one half.
  std::vector<std::pair<double, int>> all;
  for (double c : clean) all.emplace_back(c, 1);
  for (double d : degraded) all.emplace_back(d, 0);
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  double rank_sum = 0;
  for (size_t i = 0; i < all.size();) {
    size_t j = i;
    while (j < all.size() && all[j].first == all[i].first) ++j;
    const double mid_rank = 0.5 * (i + 1 + j);  // ranks i+1 .. j
    for (size_t k = i; k < j; ++k) {
      if (all[k].second) rank_sum += mid_rank;
    }
    i = j;
  }
  const double n1 = static_cast<double>(clean.size()), n0 = static_cast<double>(degraded.size());
  return (rank_sum - n1 * (n1 + 1) / 2) / (n1 * n0);
}

std::vector<float> ReplaceWithMean(const HgvaeModel& model, const std::vector<float>& windows,
                                   double share, uint64_t seed) {
  const int values = model.window() * model.coords();
  const int count = static_cast<int>(windows.size() / values);
  return model.MeanImpute(windows, RandomOcclusion(count, values, share, seed));
}

std::vector<float> ScaleBones(const Skeleton& skeleton, const std::vector<float>& windows,
                              float factor) {
  const int J = skeleton.num_joints(), N = 3 * (J - 1);
  std::vector<float> out(windows.size());
  const size_t poses = windows.size() / N;
  for (size_t p = 0; p < poses; ++p) {
    const float* src = windows.data() + p * N;
    float* dst = out.data() + p * N;
    for (int j = 1; j < J; ++j) {  // parents come first
      const int par = skeleton.parent(j);
      for (int a = 0; a < 3; ++a) {
        const float parent_src = par == 0 ? 0.0f : src[3 * (par - 1) + a];
        const float parent_dst = par == 0 ? 0.0f : dst[3 * (par - 1) + a];
        dst[3 * (j - 1) + a] = parent_dst + factor * (src[3 * (j - 1) + a] - parent_src);
      }
    }
  }
  return out;
}

std::vector<float> ShuffleFrames(const std::vector<float>& windows, int coords, uint64_t seed) {
  const size_t poses = windows.size() / coords;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, poses - 1);
  std::vector<float> out(windows.size());
  for (size_t p = 0; p < poses; ++p) {
    const size_t q = pick(rng);
    std::copy(windows.begin() + q * coords, windows.begin() + (q + 1) * coords,
              out.begin() + p * coords);
  }
  return out;
}

std::vector<Occlusion> StandardOcclusions(const Skeleton& skeleton) {
  std::vector<Occlusion> out;
  for (double s : {0.01, 0.10, 0.50, 0.90}) {
    out.push_back({"random " + std::to_string(static_cast<int>(s * 100 + 0.5)) + "%", s, {}});
  }
  // A limb: the subtree below the named joint (shoulder/hip joint itself included).
  const std::pair<const char*, std::vector<const char*>> limbs[] = {
      {"left arm", {"UpperArm_L", "LeftArm", "LShoulder"}},
      {"right arm", {"UpperArm_R", "RightArm", "RShoulder"}},
      {"left leg", {"UpperLeg_L", "LeftUpLeg", "LHip"}},
      {"right leg", {"UpperLeg_R", "RightUpLeg", "RHip"}}};
  for (const auto& [name, candidates] : limbs) {
    for (const char* c : candidates) {
      const auto j = skeleton.Find(c);
      if (!j) continue;
      Occlusion o{name, 0, {}};
      for (int k = 1; k < skeleton.num_joints(); ++k) {
        for (int a = k; a > 0; a = skeleton.parent(a)) {
          if (a == *j) {
            o.joints.push_back(k);
            break;
          }
        }
      }
      out.push_back(o);
      break;
    }
  }
  return out;
}

}  // namespace motionfork
