// Each subcommand registers itself on the top-level CLI11 app and runs from its callback.
#pragma once

#include <CLI/CLI.hpp>

namespace motionfork::pipeline {
struct PriorTrainingRequest;
}

namespace motionfork::app {

struct GlobalOptions {
  std::string config_dir;         // --config-dir
  std::string cache_dir;          // --cache-dir
  bool quiet = false;             // --quiet: no progress bars
  int exit_code = 0;              // set by a subcommand that ran
  std::vector<std::string> argv;  // the command line as given (the launcher reruns it)
};

void AddInfoCommand(CLI::App& app, GlobalOptions& global);
void AddConvertCommand(CLI::App& app, GlobalOptions& global);
void AddDatasetCommand(CLI::App& app, GlobalOptions& global);
void AddEvalCommand(CLI::App& app, GlobalOptions& global);
void AddTrainCommand(CLI::App& app, GlobalOptions& global);
void AddPredictCommand(CLI::App& app, GlobalOptions& global);
void AddPriorCommand(CLI::App& app, GlobalOptions& global);
// `prior train`'s work after the launcher (also `train`'s for a config whose prior is not there
// yet): trains or resumes, prints its reports; false when interrupted (exit code set).
bool TrainPriorOrStop(const pipeline::PriorTrainingRequest& request, GlobalOptions& global);
void AddCheckCommand(CLI::App& app, GlobalOptions& global);
void AddConstraintsCommand(CLI::App& app, GlobalOptions& global);
void AddExportCommand(CLI::App& app, GlobalOptions& global);
void AddRenderCommand(CLI::App& app, GlobalOptions& global);
void AddSynthCommand(CLI::App& app, GlobalOptions& global);
void AddBundleCommand(CLI::App& app, GlobalOptions& global);  // bundle upgrade
void AddHgvaeCommand(CLI::App& app, GlobalOptions& global);   // hgvae train (cmd_hgvae.cc)
// HG-VAE models in use (cmd_impute.cc): hgvae sample, hgvae eval, impute, ood.
void AddHgvaeSampleCommand(CLI::App& hgvae, GlobalOptions& global);
void AddHgvaeEvalCommand(CLI::App& hgvae, GlobalOptions& global);
void AddImputeCommand(CLI::App& app, GlobalOptions& global);
void AddOodCommand(CLI::App& app, GlobalOptions& global);
void AddDvaeCommand(CLI::App& app, GlobalOptions& global);  // dvae train|finetune (cmd_dvae.cc)
// Motion-DVAE models in use (cmd_denoise.cc): denoise, dvae eval.
void AddDenoiseCommand(CLI::App& app, GlobalOptions& global);
void AddDvaeEvalCommand(CLI::App& dvae, GlobalOptions& global);

}  // namespace motionfork::app
