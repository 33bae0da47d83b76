// motionfork train: train a generator from a model config on a protocol's training split.

#include <memory>

#include "app_common.h"
#include "commands.h"
#include "config/config_paths.h"
#include "flags.h"
#include "generator/training/training_run.h"
#include "generator/training/training_text.h"
#include "pipeline/prior_training.h"

namespace motionfork::app {
namespace {

struct TrainOptions {
  std::string config;
  TrainingRunFlags run;
  Precision precision = Precision::kFp32;
  CLI::Option* precision_flag = nullptr;  // given: replaces the config's training.precision
};

// Per-step progress bar and per-epoch lines.
TrainCallbacks EpochReports(std::shared_ptr<EpochBars> bars) {
  TrainCallbacks cb;
  cb.step = [bars](int epoch, double fraction,
                   const std::vector<std::pair<std::string, double>>& terms) {
    bars->Update(epoch, fraction, TrainingTermsText(terms));
  };
  cb.epoch = [bars](int epoch, const std::vector<std::pair<std::string, double>>& terms,
                    double seconds) { bars->PrintEpoch(epoch, seconds, terms, 4); };
  cb.message = PrintMessage;
  return cb;
}

void RunTrain(const TrainOptions& o, GlobalOptions& g) {
  const TrainingRunFlags& run = o.run;
  if (LaunchIfRequested(run.launch, g)) return;
  GeneratorTrainingRequest r;
  r.config_dir = ConfigDir(g.config_dir);
  r.cache_dir = CacheDir(g.cache_dir);
  r.config_path = ResolveConfigPath(r.config_dir, "models", o.config);
  r.data = run.data;
  r.split_file = run.split_file;
  r.out = run.out;
  r.epochs = run.epochs;
  r.stop_after = run.stop_after;
  if (o.precision_flag->count() > 0) r.precision = o.precision;
  StageBars stages(!g.quiet);
  GeneratorTrainingHooks hooks;
  hooks.train_prior = [&](const std::string& protocol, const std::string& out, int threads) {
    pipeline::PriorTrainingRequest prior;
    prior.protocol = protocol;
    prior.data = run.data;
    prior.split_file = run.split_file;
    prior.out = out;
    prior.threads = threads;
    return TrainPriorOrStop(prior, g);
  };
  hooks.progress = stages.Callback();
  hooks.text = [&stages](const std::string& text) {
    stages.Finish();
    PrintText(text);
  };
  hooks.epochs = [&g](int epochs) {
    return EpochReports(std::make_shared<EpochBars>(epochs, !g.quiet));
  };
  RunGeneratorTraining(r, hooks);
}

}  // namespace

void AddTrainCommand(CLI::App& app, GlobalOptions& global) {
  const auto [cmd, o] = AddSubcommand<TrainOptions>(
      &app, global, RunTrain, "train",
      R"(Train a generator (configs/models/NAME.yaml) on a protocol's training split.
Every epoch writes the bundle (OUT/model.yaml, OUT/generator.pt; OUT/constraints.yaml and
OUT/prior/ when the config names them), a row of OUT/log.csv and a checkpoint; OUT/training.yaml
records the config as read and the split. Running the same command again resumes where it
stopped (--epochs may change; another config or split is refused). A config with a `trajectory`
section then trains the trajectory network into OUT/trajectory/ (once).)");
  cmd->add_option("--config", o->config, "Model config name (configs/models/) or YAML path")
      ->required();
  AddTrainingRunOptions(cmd, &o->run, "Output folder (bundle, log, checkpoint)");
  o->precision_flag = AddPrecisionOption(
      cmd, &o->precision,
      "The residual blocks' products, forward and backward: fp32, bf16 (bfloat16 inputs, float32 "
      "sums; needs AVX512-BF16) or auto (bf16 where the CPU has it); replaces the config's "
      "training.precision (default fp32)");
}

}  // namespace motionfork::app
