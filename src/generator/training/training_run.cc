#include "generator/training/training_run.h"

#include "bundle/generator_bundle.h"
#include "config/protocol_dataset.h"
#include "generator/training/training_manifest.h"
#include "generator/training/training_setup.h"
#include "generator/training/training_text.h"
#include "generator/training/trajectory_training.h"
#include "launch/worker_place.h"
#include "validity/pose_validator.h"

namespace motionfork {
namespace {

void Say(const GeneratorTrainingHooks& hooks, const std::string& text) {
  if (hooks.text) hooks.text(text);
}

TrainCallbacks EpochReports(const GeneratorTrainingHooks& hooks, int epochs) {
  return hooks.epochs ? hooks.epochs(epochs) : TrainCallbacks{};
}

}  // namespace

bool RunGeneratorTraining(const GeneratorTrainingRequest& r, const GeneratorTrainingHooks& hooks) {
  GeneratorTrainConfig cfg = LoadGeneratorTrainConfig(r.config_path);
  if (r.epochs > 0) OverrideEpochs(&cfg.training, r.epochs);
  if (r.precision) cfg.training.precision = *r.precision;
  ResolvePrecision(cfg.training.precision);  // bf16 on a CPU without it: refused before the data
  if (IsRankZero())                          // before the data: a refused folder costs nothing
    RecordTrainingConfig(r.out, r.config_path, r.split_file, r.epochs,
                         r.precision ? PrecisionName(*r.precision) : "");
  // A prior the config names that is not there yet (a user's own dataset): trained first, where
  // the config names it, on the same data and split (configs/models/flow_prior.yaml).
  if (!cfg.prior.empty() && !PriorBundleExists(cfg.prior, r.config_dir)) {
    Say(hooks, "prior:     " + cfg.prior + " not found: training it first, on the same data\n");
    if (!hooks.train_prior) throw std::invalid_argument("prior " + cfg.prior + " not found");
    if (!hooks.train_prior(cfg.protocol, cfg.prior, cfg.training.threads)) return false;
  }
  const Dataset ds = LoadProtocolDataset(
      {cfg.protocol, r.data, r.split_file, r.config_dir, r.cache_dir}, hooks.progress);
  const Skeleton& skeleton = *ds.skeleton.skeleton;
  const ModelConfig model = TrainingModelConfig(cfg, ds.protocol, skeleton, r.split_file);
  const TrainingWindows data = BuildTrainingWindows(
      ds, cfg.training.window_stride, cfg.multimodal, model.generator.body_frame, r.cache_dir,
      [&](double f) { ReportProgress(hooks.progress, "pseudo multimodal futures", f); });
  const LossHookSources losses = MakeLossHooks(cfg, skeleton, r.config_dir);
  Say(hooks, TrainingSetupText(data, cfg.training.window_stride, losses));
  if (IsRankZero()) AttachToBundle(r.out, losses.constraints_path, losses.prior_dir);
  const TrainSummary s = TrainGenerator(cfg, model, data, r.out, losses.hooks,
                                        EpochReports(hooks, cfg.training.epochs), r.stop_after);
  Say(hooks, TrainingDoneText(s, cfg.training.epochs, r.out));
  if (cfg.trajectory && s.epochs_done == cfg.training.epochs && IsRankZero()) {
    Say(hooks, TrainTrajectoryOnce(*cfg.trajectory, model, ds, r.config_dir, r.out,
                                   EpochReports(hooks, cfg.trajectory->epochs)));
  }
  return true;
}

}  // namespace motionfork
