// motionfork::EvaluateJson (include/motionfork/evaluate.h) over the evaluation experiment of
// `motionfork eval`: this file only adapts types.
#include "motionfork/evaluate.h"

#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "config_dir.h"
#include "generator/training/eval_experiment.h"
#include "generator/training/eval_experiment_json.h"
#include "io/cache_dir.h"
#include "pipeline/motion_input.h"

namespace motionfork {

std::string EvaluateJson(const EvaluateOptions& options) {
  namespace fs = std::filesystem;
  EvalExperimentOptions e;
  if (options.predictor.empty()) {
    throw std::invalid_argument(
        "EvaluateOptions::predictor: expected a model bundle folder or a baseline "
        "(zero-velocity, constant-velocity, nearest-neighbours), got nothing");
  }
  (fs::is_directory(options.predictor) ? e.model : e.baseline) = options.predictor;
  e.protocol = options.protocol;
  e.data = options.data;
  e.subset = options.subset;
  e.split_file = options.split_file;
  e.clips = options.clips;
  e.k = options.k;
  e.seed = options.seed;
  e.fix = options.fix;
  e.repair = options.repair;
  e.threads = options.threads;
  e.config_dir = FindConfigDir(options.config_dir);
  // Shipped priors sit in models/ beside the configs folder (source tree or installed share/).
  if (!e.config_dir.empty())
    e.models_dir = (fs::path(e.config_dir).parent_path() / "models").string();
  e.cache_dir = CacheDir(options.cache_dir);
  if (!e.clips.empty()) e.conform_clips = pipeline::ConformClipsByRoles(e.config_dir, e.protocol);
  return EvalExperimentJson(e, RunEvalExperiment(e)).dump(2);
}

}  // namespace motionfork
