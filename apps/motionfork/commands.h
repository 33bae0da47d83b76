// Each subcommand registers itself on the top-level CLI11 app and runs from its callback.
#pragma once

#include <CLI/CLI.hpp>

namespace motionfork::app {

struct GlobalOptions {
  std::string config_dir;  // --config-dir
  std::string cache_dir;   // --cache-dir
  bool quiet = false;      // --quiet: no progress bars
  int exit_code = 0;       // set by a subcommand that ran
};

void AddInfoCommand(CLI::App& app, GlobalOptions& global);
void AddConvertCommand(CLI::App& app, GlobalOptions& global);
void AddDatasetCommand(CLI::App& app, GlobalOptions& global);
void AddEvalCommand(CLI::App& app, GlobalOptions& global);
void AddTrainCommand(CLI::App& app, GlobalOptions& global);
void AddPredictCommand(CLI::App& app, GlobalOptions& global);
void AddPriorCommand(CLI::App& app, GlobalOptions& global);
void AddCheckCommand(CLI::App& app, GlobalOptions& global);
void AddConstraintsCommand(CLI::App& app, GlobalOptions& global);
void AddExportCommand(CLI::App& app, GlobalOptions& global);
void AddRenderCommand(CLI::App& app, GlobalOptions& global);
void AddSynthCommand(CLI::App& app, GlobalOptions& global);
void AddHgvaeCommand(CLI::App& app, GlobalOptions& global);  // hgvae train|sample|eval, impute, ood

}  // namespace motionfork::app
