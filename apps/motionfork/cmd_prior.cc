// motionfork prior train|score|sample: the pose prior (GSPS normalizing flow on limb directions).
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "app_common.h"
#include "bundle/prior_bundle.h"
#include "commands.h"
#include "core/interrupt.h"
#include "flags.h"
#include "io/motion_file.h"
#include "motion_options.h"
#include "pipeline/prior_score.h"
#include "pipeline/prior_score_json.h"
#include "pipeline/prior_score_text.h"
#include "pipeline/prior_training.h"
#include "pipeline/prior_training_text.h"
#include "torch_util/threads.h"

namespace motionfork::app {
namespace {

constexpr int kExitInterrupted = 130;  // 128 + SIGINT, as shells report it

struct ScoreOptions {
  std::string file;
  std::string model;
  MotionInputOptions input;
  std::string json;
  bool summary_only = false;
};

struct SampleOptions {
  std::string model;
  int count = 0;
  std::string output;
  uint64_t seed = 0;
  double temperature = 1.0;
  int steps = 1000;
};

// ---------------------------------------------------------------------------------------------
// train

// Per-epoch bars on a terminal only: in a log the epoch lines say it all.
PriorTrainCallbacks EpochReports(const GlobalOptions& g, const std::string& checkpoint,
                                 std::shared_ptr<std::unique_ptr<EpochBars>> bars) {
  const bool enabled = !g.quiet && isatty(fileno(stderr));
  PriorTrainCallbacks callbacks;
  callbacks.stop_requested = InterruptRequest::requested;
  callbacks.progress = [=](const PriorTrainProgress& p) {
    if (!*bars) {
      if (p.epoch > 0)
        PrintText(StringPrintf("resuming:  %s holds %d of %d epochs\n", checkpoint.c_str(), p.epoch,
                               p.epochs));
      *bars = std::make_unique<EpochBars>(p.epochs, enabled);
    }
    if (!p.epoch_done) {
      (*bars)->Update(p.epoch, static_cast<double>(p.step) / p.steps_per_epoch,
                      StringPrintf("NLL %.3f", p.train_nll));
      return;
    }
    (*bars)->Finish();
    if (pipeline::PriorEpochGetsLine(p.epoch, p.epochs)) PrintText(pipeline::PriorEpochText(p));
    std::fflush(stdout);
  };
  return callbacks;
}

struct PriorTrainCmd {
  pipeline::PriorTrainingRequest request;
  LaunchOptions launch;
};

void RunTrain(const PriorTrainCmd& c, GlobalOptions& g) {
  if (LaunchIfRequested(c.launch, g)) return;
  TrainPriorOrStop(c.request, g);
}

}  // namespace

bool TrainPriorOrStop(const pipeline::PriorTrainingRequest& request, GlobalOptions& g) {
  pipeline::PriorTrainingRequest o = request;
  o.config_dir = ConfigDir(g.config_dir);
  o.cache_dir = CacheDir(g.cache_dir);
  o.threads = o.threads > 0 ? o.threads : DefaultThreads();
  PinThreads(o.threads);
  StageBars loading(!g.quiet);
  auto bars = std::make_shared<std::unique_ptr<EpochBars>>();
  pipeline::PriorTrainingCallbacks callbacks;
  callbacks.loading = loading.Callback();
  callbacks.started = [&](const PosePrior& prior, const PriorData& data, const std::string& path) {
    loading.Finish();
    PrintText(pipeline::PriorTrainingStartText(prior, data, path, o));
    std::fflush(stdout);
  };
  callbacks.training =
      EpochReports(g, (std::filesystem::path(o.out) / "checkpoint.pt").string(), bars);
  const pipeline::PriorTrainingRun run = [&] {
    const InterruptRequest ctrl_c;
    return pipeline::TrainPriorBundle(o, callbacks);
  }();
  bars->reset();
  if (!run.completed) {
    PrintText(pipeline::PriorTrainingInterruptedText(o.out));
    g.exit_code = kExitInterrupted;
    return false;
  }
  PrintText(pipeline::PriorTrainingDoneText(run, o.out));
  return true;
}

namespace {

// ---------------------------------------------------------------------------------------------
// score

void RunScore(const ScoreOptions& o, const GlobalOptions& g) {
  const PosePrior prior = LoadPosePrior(o.model);
  const std::string config_dir = ConfigDir(g.config_dir);
  const LoadedMotion lm = pipeline::LoadMotionInput(o.file, WithConfigDir(o.input, config_dir));
  std::vector<std::string> notes;
  const Motion motion = pipeline::OnPriorSkeleton(lm, prior, config_dir, &notes);
  PrintInputNotes(o.file, notes);
  const pipeline::PriorScore s = pipeline::ScorePoses(prior, motion);
  if (o.json == "-") {
    EmitJson("-", pipeline::PriorScoreJson(o.file, o.model, prior, motion, s));
    return;
  }
  PrintText(pipeline::PriorScoreText(o.file, o.model, prior, motion, s, !o.summary_only));
  EmitJson(o.json, pipeline::PriorScoreJson(o.file, o.model, prior, motion, s));
}

// ---------------------------------------------------------------------------------------------
// sample

void RunSample(const SampleOptions& o, const GlobalOptions&) {
  RequireArgument(o.output, "-o,--out");
  FormatOfPath(o.output);  // fail on an unsupported extension before any work
  const PosePrior prior = LoadPosePrior(o.model);
  const double fps = prior.summary().fps > 0 ? prior.summary().fps : 30.0;
  const Motion poses = prior.Sample(o.count, o.seed, o.temperature, {}, fps, o.steps);
  WriteMotionFile(o.output, poses);
  PrintText(pipeline::PriorSampleText(prior, o.count, o.output));
}

void AddPriorTrain(CLI::App* prior, GlobalOptions& global) {
  const auto [train, t] = AddSubcommand<PriorTrainCmd>(
      prior, global, RunTrain, "train",
      "Train a pose prior on single frames of a protocol's training split");
  train->footer(
      "A share of the training clips is held out to measure the NLL after every epoch; the test\n"
      "split is scored once at the end. A checkpoint is written to OUT after every epoch and an\n"
      "interrupted run (Ctrl-C) resumes when the same command is run again. Result: "
      "OUT/prior.yaml\n"
      "+ OUT/weights.npy (the bundle) and OUT/train_log.tsv. Threads: --threads, else\n"
      "$MOTIONFORK_THREADS, else 1.");
  train
      ->add_option("--protocol", t->request.protocol,
                   "Protocol name (bandai, h36m, humaneva) or YAML path")
      ->required();
  AddDataOptions(train, &t->request.data, &t->request.split_file,
                 "Data folder of the protocol (see 'motionfork dataset stats')");
  train->add_option("--out", t->request.out, "Output folder for the bundle and the checkpoint")
      ->required();
  train->add_option("--config", t->request.config,
                    "Prior config name in configs/models/ or YAML path (default: flow_prior)");
  train
      ->add_option("--threads", t->request.threads,
                   "LibTorch/BLAS threads (default $MOTIONFORK_THREADS or 1)")
      ->check(PositiveNumber);
  train->add_flag("--restart", t->request.restart,
                  "Discard a checkpoint or trained prior in OUT and train from the start");
  AddLauncherOptions(train, &t->launch);
}

void AddPriorScore(CLI::App* prior, GlobalOptions& global) {
  const auto [score, s] = AddSubcommand<ScoreOptions>(
      prior, global, RunScore, "score",
      "Per-frame negative log-likelihood of a motion under a prior, and a summary");
  score->footer(
      "NLL is in nats per pose; lower = more plausible. The summary compares the frames with what\n"
      "real held-out poses scored in training (frames above their 99th percentile are flagged).\n"
      "The motion is put on the prior's skeleton: by joint names, by index (.npy), or through the\n"
      "skeleton config the prior was trained with (e.g. a 22-joint Bandai BVH).");
  AddInputFile(score, "MOTION", &s->file, "Motion file (.bvh, .npy, .csv)");
  AddModelOption(score, &s->model, "Prior bundle folder (holding prior.yaml)");
  AddMotionInputOptions(score, &s->input);
  AddJsonOption(score, &s->json, "The per-frame NLL and the summary, instead of text,");
  score->add_flag("--summary-only", s->summary_only, "Text output without the per-frame table");
}

void AddPriorSample(CLI::App* prior, GlobalOptions& global) {
  const auto [sample, m] = AddSubcommand<SampleOptions>(
      prior, global, RunSample, "sample", "Draw poses from a prior into a motion file");
  sample->footer(
      "Poses come from the prior's density on valid poses (unit limb directions): flow samples\n"
      "normalised, then Metropolis-Hastings steps (--steps) that move them to where the prior "
      "puts\n"
      "real poses. One pose per frame, root at the origin, the training data's mean bone lengths,\n"
      "at the protocol's frame rate.");
  AddModelOption(sample, &m->model, "Prior bundle folder (holding prior.yaml)");
  sample->add_option("-n,--count", m->count, "Number of poses")->required()->check(PositiveNumber);
  sample->add_option("-o,--out", m->output, "Output file (.npy [N, J, 3] or .csv; required)");
  AddDeprecatedOption(sample, "--output", "-o/--out", &m->output);
  sample->add_option("--seed", m->seed, "Random seed (default 0)")->check(Seed);
  sample
      ->add_option("--temperature", m->temperature,
                   "Sample p^(1/T) (default 1; < 1 gives more typical poses)")
      ->check(PositiveNumber);
  sample
      ->add_option("--steps", m->steps,
                   "Metropolis-Hastings steps (default 1000; 0 = raw flow samples, fast but mostly "
                   "implausible)")
      ->check(NonNegativeNumber);
}

}  // namespace

void AddPriorCommand(CLI::App& app, GlobalOptions& global) {
  CLI::App* prior = app.add_subcommand(
      "prior", "Pose prior: a normalizing flow on limb directions that scores and samples poses");
  prior->require_subcommand(1);
  AddPriorTrain(prior, global);
  AddPriorScore(prior, global);
  AddPriorSample(prior, global);
}

}  // namespace motionfork::app
