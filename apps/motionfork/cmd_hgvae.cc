// motionfork hgvae: the HG-VAE motion-window model: train, sample, evaluate.
#include <cstdio>
#include <functional>

#include "app_common.h"
#include "bundle/hgvae_bundle.h"
#include "commands.h"
#include "config/config_paths.h"
#include "experiment_common.h"
#include "flags.h"
#include "imputation/training/gaussian_fitting.h"
#include "imputation/training/hgvae_training.h"
#include "imputation/training/hgvae_training_text.h"
#include "imputation/training/refiner_calibration.h"
#include "io/file_util.h"

namespace motionfork::app {
namespace {

struct HgvaeTrainCmd {
  std::string config = "hgvae_bandai";
  std::string prior;  // hgvae refine: the bundle to add the refiner to
  TrainingRunFlags run;
};

HgvaeTrainCallbacks EpochReports(EpochBars* bars) {
  HgvaeTrainCallbacks cb;
  cb.step = [bars](int epoch, double fraction, double loss, double nll, double kl) {
    char detail[96];
    std::snprintf(detail, sizeof(detail), "loss %.4g nll %.4g kl %.4g", loss, nll, kl);
    bars->Update(epoch, fraction, detail);
  };
  cb.epoch = [bars](const HgvaeEpochLog& log) {
    bars->PrintEpoch(log.epoch, log.seconds, log.terms, 5, log.kl_weight);
  };
  cb.message = PrintMessage;
  return cb;
}

void RunHgvaeTrain(const HgvaeTrainCmd& o, GlobalOptions& g) {
  const TrainingRunFlags& run = o.run;
  if (LaunchIfRequested(run.launch, g)) return;
  HgvaeTrainConfig cfg =
      LoadHgvaeTrainConfig(ResolveConfigPath(ConfigDir(g.config_dir), "models", o.config));
  if (run.epochs > 0) cfg.training.epochs = run.epochs;
  const Dataset ds = LoadProtocolDataset(cfg.protocol, run.data, run.split_file, g);
  const ProtocolOptions& protocol = ds.protocol;
  const int coords = 3 * (ds.skeleton.skeleton->num_joints() - 1);
  const HgvaeManifest base = HgvaeTrainingManifest(cfg, protocol, *ds.skeleton.skeleton);
  cfg.model = ResolveHgvaeOptions(cfg.model, coords, protocol.t_his);
  const HgvaeData data = MakeHgvaeData(ds, cfg.training, cfg.model.window);
  PrintText(HgvaeDataText(data, cfg.model.window));
  EpochBars bars(cfg.training.epochs, !g.quiet);
  const HgvaeTrainSummary s =
      TrainHgvae(cfg, base, data, run.out, EpochReports(&bars), run.stop_after);
  if (s.first_epoch >= cfg.training.epochs && IsRankZero())
    RefreshBundleSettings(run.out, data, cfg);
  PrintText(HgvaeTrainingDoneText(s, cfg, run.out));
}

void RunHgvaeRefine(const HgvaeTrainCmd& o, GlobalOptions& g) {
  const TrainingRunFlags& run = o.run;
  if (LaunchIfRequested(run.launch, g)) return;
  HgvaeTrainConfig cfg =
      LoadHgvaeTrainConfig(ResolveConfigPath(ConfigDir(g.config_dir), "models", o.config));
  if (run.epochs > 0) cfg.refiner.training.epochs = run.epochs;
  const Dataset ds = LoadProtocolDataset(cfg.protocol, run.data, run.split_file, g);
  const HgvaeData data = MakeHgvaeData(ds, cfg.training, cfg.refiner.model.window);
  PrintText(HgvaeDataText(data, cfg.refiner.model.window));
  EpochBars bars(cfg.refiner.training.epochs, !g.quiet);
  const HgvaeTrainSummary s = RefineHgvae(
      cfg, o.prior, data, run.out, LossEpochReports<HgvaeRefineCallbacks>(&bars), run.stop_after);
  PrintText(HgvaeRefineDoneText(s, run.out));
}

struct CalibrateCmd {
  std::string command;  // calibrate, fit-gaussian
  std::string config = "hgvae_bandai", model, data, split_file, out;
};

// Both fits after the refiner read the config's split as its training did: the clips it trained
// on and the ones it held out. `fit` writes OUT and says what it did.
void RunHgvaeFit(
    const CalibrateCmd& o, GlobalOptions& g,
    const std::function<std::string(const HgvaeData&, uint64_t seed, const StageProgress&)>& fit) {
  RequireSeparateFolder(o.command, o.out, o.model);  // before the dataset's 20 s
  const HgvaeTrainConfig cfg =
      LoadHgvaeTrainConfig(ResolveConfigPath(ConfigDir(g.config_dir), "models", o.config));
  const Dataset ds = LoadProtocolDataset(cfg.protocol, o.data, o.split_file, g);
  const HgvaeData data = MakeHgvaeData(ds, cfg.training, cfg.refiner.model.window);
  StageBars bars(!g.quiet);
  const std::string text = fit(data, cfg.refiner.training.seed, bars.Callback());
  bars.Finish();
  PrintText(text);
}

void RunHgvaeCalibrate(const CalibrateCmd& o, GlobalOptions& g) {
  RunHgvaeFit(o, g, [&o](const HgvaeData& data, uint64_t seed, const StageProgress& progress) {
    return RefinerCalibrationText(
        CalibrateHgvaeBundle(o.model, data.held_out.poses, seed, o.out, progress), o.out);
  });
}

void RunHgvaeFitGaussian(const CalibrateCmd& o, GlobalOptions& g) {
  RunHgvaeFit(o, g, [&o](const HgvaeData& data, uint64_t seed, const StageProgress& progress) {
    return GaussianFitText(FitGaussianIntoBundle(o.model, data.train.poses, data.held_out.poses,
                                                 seed + 29, o.out, progress),
                           o.out);
  });
}

void AddFitOptions(CLI::App* cmd, CalibrateCmd* o) {
  o->command = cmd->get_name();
  cmd->add_option("--config", o->config, "Config name or YAML path (default hgvae_bandai)");
  AddModelOption(cmd, &o->model, "HG-VAE bundle with a refiner");
  AddDataOptions(cmd, &o->data, &o->split_file, "Data folder of the model's protocol");
  cmd->add_option("--out", o->out, "Output bundle folder (not MODEL)")->required();
}

}  // namespace

void AddHgvaeCommand(CLI::App& app, GlobalOptions& global) {
  CLI::App* hg = app.add_subcommand(
      "hgvae",
      "HG-VAE: a hierarchical graph-convolutional VAE of motion windows (imputation of missing\n"
      "values, out-of-distribution scores, sampling). See also 'motionfork impute' and 'motionfork "
      "ood'.");
  hg->require_subcommand(1);
  const char* kTrain =
      R"(Train an HG-VAE (configs/models/NAME.yaml) on a protocol's training split. Every epoch writes
the bundle (OUT/hgvae.yaml, OUT/hgvae.pt), a row of OUT/log.csv and a checkpoint; running the
same command again resumes where it stopped.)";
  const char* kRefine =
      R"(Train the imputation refiner of an HG-VAE bundle (the config's 'refiner'): a temporal
convolution network learns, on clean training windows with random masks (values at random, gaps
of a joint, a limb or a body part), to correct their spline, linear and rigid-limb fills. OUT: the
bundle with its refiner (impute start 'refiner'). Early stopping; resumable.)";
  for (const bool refining : {false, true}) {
    const auto [cmd, t] =
        AddSubcommand<HgvaeTrainCmd>(hg, global, refining ? RunHgvaeRefine : RunHgvaeTrain,
                                     refining ? "refine" : "train", refining ? kRefine : kTrain);
    cmd->add_option("--config", t->config,
                    "Config name (configs/models/) or YAML path (default hgvae_bandai)");
    AddTrainingRunOptions(cmd, &t->run, "Output folder (bundle, log, checkpoint)");
    if (refining) cmd->add_option("--prior", t->prior, "HG-VAE bundle")->required();
  }
  const auto [cal, c] = AddSubcommand<CalibrateCmd>(
      hg, global, RunHgvaeCalibrate, "calibrate",
      R"(Fit how much of the refiner's correction and of a local polynomial's to keep per kind of
missing value (gap length x edge speed x how crowded the frame is), whether to keep bone lengths,
and how far to adapt those weights to each motion (refiner_adapt_values, per gap length, chosen by
cross-fitting),
on the training clips the refiner held out (the config's split), every standard gap setting drawn
on each; OUT: the bundle with them (refiner_weights, refiner_local_weights, ...).)");
  AddFitOptions(cal, c.get());
  const auto [ends, e] = AddSubcommand<CalibrateCmd>(
      hg, global, RunHgvaeFitGaussian, "fit-gaussian",
      R"(Fit the fill of values observed on one side only (a history's last frames): a Gaussian over
windows of the model's length, fitted on the training clips the HG-VAE trained on; each such value
becomes its conditional mean given what its window observes. Taken when it beats the bundle's own
last stage on histories of the held-out training clips (random 10/50/90% missing); OUT: the bundle
with it (refiner_gaussian, window_gaussian.npy).)");
  AddFitOptions(ends, e.get());
  AddHgvaeSampleCommand(*hg, global);
  AddHgvaeEvalCommand(*hg, global);
}

}  // namespace motionfork::app
