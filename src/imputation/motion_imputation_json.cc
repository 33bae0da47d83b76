#include "imputation/motion_imputation_json.h"

#include <nlohmann/json.hpp>

#include "imputation/motion_imputation_summary.h"

namespace motionfork {

nlohmann::ordered_json WindowScoresJson(const HgvaeModel& model,
                                        const std::vector<WindowScore>& scores,
                                        const std::string& model_path,
                                        const std::string& motion_path) {
  nlohmann::ordered_json windows = nlohmann::ordered_json::array();
  for (const WindowScore& s : scores) {
    windows.push_back({{"start", s.start},
                       {"frames", model.window()},
                       {"score", s.score},
                       {"out_of_distribution", s.out_of_distribution}});
  }
  const HgvaeManifest& m = model.manifest();
  return {{"model", model_path},
          {"motion", motion_path},
          {"score", ToString(m.ood_score)},
          {"threshold", model.OodThreshold()},
          {"score_mean", m.score_mean},
          {"score_std", m.score_std},
          {"k", m.ood_k},
          {"flagged", CountOutOfDistribution(scores)},
          {"windows", windows}};
}

}  // namespace motionfork
