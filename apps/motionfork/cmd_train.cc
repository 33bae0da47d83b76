// motionfork train: train a generator from a model config on a protocol's training split.

#include "app_common.h"
#include "bundle/generator_bundle.h"
#include "commands.h"
#include "config/config_paths.h"
#include "dataset/dataset.h"
#include "experiment_common.h"
#include "flags.h"
#include "generator/training/training.h"
#include "generator/training/training_manifest.h"
#include "generator/training/training_setup.h"
#include "generator/training/training_text.h"
#include "generator/training/trajectory_training.h"
#include "pipeline/prior_training.h"
#include "validity/pose_validator.h"

namespace motionfork::app {
namespace {

struct TrainOptions {
  std::string config;
  TrainingRunFlags run;
  Precision precision = Precision::kFp32;
  CLI::Option* precision_flag = nullptr;  // given: replaces the config's training.precision
};

// Per-step progress bar and per-epoch lines.
TrainCallbacks EpochReports(EpochBars* bars) {
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
  const std::string config_dir = ConfigDir(g.config_dir);
  const std::string config_path = ResolveConfigPath(config_dir, "models", o.config);
  GeneratorTrainConfig cfg = LoadGeneratorTrainConfig(config_path);
  if (run.epochs > 0) OverrideEpochs(&cfg.training, run.epochs);
  const bool precision_given = o.precision_flag->count() > 0;
  if (precision_given) cfg.training.precision = o.precision;
  ResolvePrecision(cfg.training.precision);  // bf16 on a CPU without it: refused before the data
  if (IsRankZero())                          // before the data: a refused folder costs nothing
    RecordTrainingConfig(run.out, config_path, run.split_file, run.epochs,
                         precision_given ? PrecisionName(o.precision) : "");
  // A prior the config names that is not there yet (a user's own dataset): trained first, where
  // the config names it, on the same data and split (configs/models/flow_prior.yaml).
  if (!cfg.prior.empty() && !PriorBundleExists(cfg.prior, config_dir)) {
    PrintText("prior:     " + cfg.prior + " not found: training it first, on the same data\n");
    pipeline::PriorTrainingRequest prior;
    prior.protocol = cfg.protocol;
    prior.data = run.data;
    prior.split_file = run.split_file;
    prior.out = cfg.prior;
    prior.threads = cfg.training.threads;
    if (!TrainPriorOrStop(prior, g)) return;
  }
  const Dataset ds = LoadProtocolDataset(cfg.protocol, run.data, run.split_file, g);
  const Skeleton& skeleton = *ds.skeleton.skeleton;
  const ModelConfig model = TrainingModelConfig(cfg, ds.protocol, skeleton, run.split_file);
  TrainingWindows data;
  {
    ProgressBar bar("pseudo multimodal futures", !g.quiet);
    data = BuildTrainingWindows(ds, cfg.training.window_stride, cfg.multimodal,
                                model.generator.body_frame, CacheDir(g.cache_dir),
                                [&bar](double f) { bar.Update(f); });
  }
  const LossHookSources losses = MakeLossHooks(cfg, skeleton, config_dir);
  PrintText(TrainingSetupText(data, cfg.training.window_stride, losses));
  if (IsRankZero()) AttachToBundle(run.out, losses.constraints_path, losses.prior_dir);
  EpochBars bars(cfg.training.epochs, !g.quiet);
  const TrainSummary s =
      TrainGenerator(cfg, model, data, run.out, losses.hooks, EpochReports(&bars), run.stop_after);
  PrintText(TrainingDoneText(s, cfg.training.epochs, run.out));
  if (cfg.trajectory && s.epochs_done == cfg.training.epochs && IsRankZero()) {
    EpochBars trajectory_bars(cfg.trajectory->epochs, !g.quiet);  // where the root goes (issue 27)
    PrintText(TrainTrajectoryOnce(*cfg.trajectory, model, ds, config_dir, run.out,
                                  EpochReports(&trajectory_bars)));
  }
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
