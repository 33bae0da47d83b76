// `motionfork ood`'s report as JSON: a motion's window scores under an HG-VAE and the bundle's
// out-of-distribution rule.
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "imputation/hgvae_model.h"
#include "imputation/motion_imputation.h"

namespace motionfork {

// model_path, motion_path: as the user named them.
nlohmann::ordered_json WindowScoresJson(const HgvaeModel& model,
                                        const std::vector<WindowScore>& scores,
                                        const std::string& model_path,
                                        const std::string& motion_path);

}  // namespace motionfork
