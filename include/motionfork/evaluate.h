// motionfork's evaluation API: a predictor on a protocol's test windows, as `motionfork eval`
// measures it. Apart from motionfork.h (and its target, motionfork_api_eval) because it carries the
// evaluation and dataset-reading code that a program which only predicts does not link
// (ARCHITECTURE.md). Build tree only for now: the Python module's evaluate() is its user.
#pragma once

#include <cstdint>
#include <string>

namespace motionfork {

// What Evaluate measures: a predictor on a protocol's test windows, as `motionfork eval` does.
struct EvaluateOptions {
  // A model bundle folder, or a baseline: "zero-velocity", "constant-velocity" or
  // "nearest-neighbours".
  std::string predictor;
  std::string protocol;         // protocol name (bandai, h36m, humaneva) or YAML path
  std::string data;             // the protocol's data folder (test clips and the training clips)
  std::string subset = "test";  // clips of data evaluated: test, train or all
  std::string split_file;       // overrides the protocol's split file; "" = the protocol's
  std::string clips;            // evaluate this folder of motion files instead; "" = data's
  int k = 50;                   // futures per history, >= 2
  uint64_t seed = 0;
  std::string fix;         // a part every sample shares (the controllable setting); "" = none
  bool repair = true;      // a model's angle-range repair
  int threads = 0;         // windows measured at once; 0 = every core
  std::string config_dir;  // as LoadOptions::config_dir
  // Parsed datasets and multimodal sets, as the command's --cache-dir: "" = $MOTIONFORK_CACHE_DIR,
  // else ~/.cache/motionfork; "none" = no cache.
  std::string cache_dir;
};

// APD, ADE, FDE, MMADE, MMFDE (metres), overall and per action, and the validity figures: the
// JSON document `motionfork eval --json` prints, the same figures for the same options. Throws
// std::invalid_argument for bad options, std::runtime_error for missing or malformed files.
std::string EvaluateJson(const EvaluateOptions& options);

}  // namespace motionfork
