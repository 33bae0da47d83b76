// motionfork prior train|score|sample: the pose prior (GSPS normalizing flow on limb directions).
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "app_common.h"
#include "bundle/prior_bundle.h"
#include "commands.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "core/error.h"
#include "dataset/dataset.h"
#include "dataset_loading.h"
#include "flags.h"
#include "flow/pose_prior.h"
#include "flow/prior_data.h"
#include "flow/trainer.h"
#include "io/file_util.h"
#include "io/motion_file.h"
#include "motion_options.h"
#include "torch_util/threads.h"

namespace motionfork::app {
namespace {

namespace fs = std::filesystem;

constexpr int kExitInterrupted = 130;  // 128 + SIGINT, as shells report it
constexpr const char* kCheckpointFile = "checkpoint.pt";

std::atomic<bool> g_stop{false};
extern "C" void OnSigint(int) { g_stop = true; }

struct TrainOptions {
  std::string protocol;
  std::string data;
  std::string out;
  std::string config = "flow_prior";
  std::string split_file;
  bool restart = false;
  int threads = 0;
};

struct ScoreOptions {
  std::string file;
  std::string model;
  MotionInputOptions input;
  bool json = false;
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

std::string Fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

std::string JsonNumber(double v) { return std::isfinite(v) ? Fmt("%.6g", v) : "null"; }

std::string JsonEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// train

void RunTrain(const TrainOptions& o, GlobalOptions& g) {
  const std::string config_dir = ConfigDir(g.config_dir);
  const std::string config_path = ResolveConfigPath(config_dir, "models", o.config);
  const PriorConfig config = LoadFlowConfig(config_path);
  const int threads = o.threads > 0 ? o.threads : DefaultThreads();
  PinThreads(threads);

  const fs::path out(o.out);
  const fs::path checkpoint = out / kCheckpointFile;
  const fs::path manifest = out / "prior.yaml";
  if (o.restart) {
    std::error_code ec;
    fs::remove(checkpoint, ec);
  } else if (!fs::exists(checkpoint) && fs::exists(manifest)) {
    throw std::invalid_argument(
        o.out +
        " already holds a trained prior (prior.yaml) and no checkpoint to resume: pass "
        "--restart to train it again, or choose another --out");
  }

  const ProtocolOptions protocol =
      LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", o.protocol));
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", protocol.skeleton));
  const Dataset ds = LoadDatasetWithProgress(protocol, skeleton, o.data, o.split_file, g);
  const PriorData data = MakePriorData(ds, config.training);

  PosePrior prior(skeleton.skeleton, config);
  prior.set_skeleton_config(protocol.skeleton);
  prior.mutable_summary().protocol = protocol.name;
  prior.mutable_summary().fps = protocol.fps;
  prior.mutable_summary().threads = threads;

  const PriorTrainOptions& t = config.training;
  std::printf(
      "prior:     %d layers, %d reflections each, %s parameters, %d numbers per pose (%s)\n",
      prior.config().model.num_layers, prior.config().model.num_reflections,
      WithThousands(prior.num_parameters()).c_str(), prior.dim(), config_path.c_str());
  std::printf(
      "data:      %s, protocol %s: train %s frames (%s clips), held-out %s frames (%s "
      "training clips, %.0f%%), test %s frames",
      o.data.c_str(), protocol.name.c_str(), WithThousands(data.train.size()).c_str(),
      WithThousands(data.train_clips).c_str(), WithThousands(data.held_out.size()).c_str(),
      WithThousands(static_cast<long long>(data.held_out_clips.size())).c_str(),
      100 * t.held_out_share, WithThousands(data.test.size()).c_str());
  if (t.frame_stride > 1) std::printf(", every %d-th frame", t.frame_stride);
  if (data.dropped_frames > 0) {
    std::printf(", %s frames skipped (zero-length bone)",
                WithThousands(data.dropped_frames).c_str());
  }
  std::printf(
      "\ntraining:  %d epochs, batch %d, Adam lr %g (constant %d epochs, then linear), weight "
      "decay %g, seed %llu, %d thread%s\n",
      t.epochs, t.batch_size, t.learning_rate, t.constant_epochs, t.weight_decay,
      static_cast<unsigned long long>(t.seed), threads, threads == 1 ? "" : "s");
  std::fflush(stdout);

  fs::create_directories(out);
  g_stop = false;
  auto previous = std::signal(SIGINT, OnSigint);
  // Per-epoch bars on a terminal only: in a log the epoch lines say it all.
  const bool bars = !g.quiet && isatty(fileno(stderr));
  std::unique_ptr<ProgressBar> bar;
  bool announced = false;
  PriorTrainCallbacks callbacks;
  callbacks.stop_requested = [] { return g_stop.load(); };
  callbacks.progress = [&](const PriorTrainProgress& p) {
    if (!announced) {
      announced = true;
      if (p.epoch > 0) {
        std::printf("resuming:  %s holds %d of %d epochs\n", checkpoint.c_str(), p.epoch, p.epochs);
        std::fflush(stdout);
      }
    }
    if (!p.epoch_done) {
      if (!bar) {
        bar = std::make_unique<ProgressBar>(
            "epoch " + std::to_string(p.epoch + 1) + "/" + std::to_string(p.epochs), bars);
      }
      bar->Update(static_cast<double>(p.step) / p.steps_per_epoch,
                  "NLL " + Fmt("%.3f", p.train_nll));
      return;
    }
    bar.reset();
    std::printf("epoch %2d/%d  lr %.2e  train NLL %9.4f  held-out NLL %9.4f  (%s)\n", p.epoch + 1,
                p.epochs, p.learning_rate, p.train_nll, p.held_out_nll,
                Duration(p.epoch_seconds).c_str());
    std::fflush(stdout);
  };
  PriorTrainOutcome outcome;
  try {
    outcome = TrainPosePrior(prior, data, checkpoint.string(), callbacks);
  } catch (...) {
    std::signal(SIGINT, previous);
    throw;
  }
  std::signal(SIGINT, previous);
  bar.reset();
  if (!outcome.completed) {
    std::printf(
        "interrupted: the checkpoint in %s keeps every finished epoch; run the same command "
        "to resume\n",
        o.out.c_str());
    g.exit_code = kExitInterrupted;
    return;
  }
  SavePosePrior(prior, o.out);
  const PriorTrainingSummary& y = prior.summary();
  std::string log = "epoch\tlearning_rate\ttrain_nll\theld_out_nll\n";
  for (size_t e = 0; e < y.train_nll.size(); ++e) {
    log += std::to_string(e + 1) + "\t" + Fmt("%.6g", PriorLearningRate(t, static_cast<int>(e))) +
           "\t" + Fmt("%.6f", y.train_nll[e]) + "\t" + Fmt("%.6f", y.held_out_nll[e]) + "\n";
  }
  WriteFileAtomically((out / "train_log.tsv").string(), log);
  std::error_code ec;
  fs::remove(checkpoint, ec);  // the bundle holds everything; a re-run must say --restart
  std::printf(
      "done:      held-out NLL %.4f (median %.4f, 99th percentile %.4f), test NLL %.4f "
      "nats per pose; %s of training\n",
      y.held_out_nll.empty() ? std::nan("") : y.held_out_nll.back(), y.held_out_nll_q50,
      y.held_out_nll_q99, y.test_nll, Duration(y.seconds).c_str());
  std::printf("bundle:    %s (prior.yaml, weights.npy, train_log.tsv)\n", o.out.c_str());
}

// ---------------------------------------------------------------------------------------------
// score

// The motion on the prior's skeleton: as stored, bound by index (.npy), or mapped through the
// skeleton config the prior was trained with (e.g. a Bandai BVH of 22 joints onto 17).
Motion OnPriorSkeleton(const LoadedMotion& lm, const PosePrior& prior,
                       const std::string& config_dir) {
  const Motion& m = lm.motion;
  const Skeleton& want = prior.skeleton();
  if (m.skeleton().SameStructure(want)) return m;
  if (m.skeleton().is_anonymous() && m.num_joints() == want.num_joints() &&
      m.skeleton().joint_name(0) == "j0") {
    return Motion(prior.skeleton_ptr(), m.fps(), m.positions());
  }
  std::string by_name;  // why the joints do not map by name
  {
    // Named joints in another order (e.g. a CSV): re-ordered by name.
    SkeletonConfig same;
    same.source = same.skeleton = prior.skeleton_ptr();
    try {
      return ConformToSkeleton(m, same);
    } catch (const std::invalid_argument& e) {
      by_name = e.what();  // other names: try the training skeleton config below
    }
  }
  if (!lm.skeleton_config && !prior.skeleton_config().empty()) {
    std::optional<SkeletonConfig> sc;
    try {
      sc = LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", prior.skeleton_config()));
    } catch (const std::exception&) {
      // Not available here: the skeleton check below says what is expected.
    }
    if (sc && sc->skeleton->SameStructure(want)) {
      try {
        return ConformToSkeleton(m, *sc);
      } catch (const std::invalid_argument&) {
        // Not this skeleton's joints: reported below.
      }
    }
  }
  if (m.skeleton().is_anonymous() && m.skeleton().joint_name(0) != "j0") {
    // Named joints without a tree (CSV): say which names are missing.
    throw std::invalid_argument("the prior expects poses of skeleton '" + want.name() + "' (" +
                                std::to_string(want.num_joints()) + " joints); " + by_name +
                                " (pass --skeleton NAME to map the file onto a skeleton)");
  }
  prior.CheckSkeleton(m.skeleton());
  return m;
}

void RunScore(const ScoreOptions& o, const GlobalOptions& g) {
  const PosePrior prior = LoadPosePrior(o.model);
  const std::string config_dir = ConfigDir(g.config_dir);
  const LoadedMotion lm = pipeline::LoadMotionInput(o.file, WithConfigDir(o.input, config_dir));
  const Motion motion = OnPriorSkeleton(lm, prior, config_dir);
  std::vector<double> nll = prior.LogProb(motion);
  for (double& v : nll) v = -v;
  const int T = static_cast<int>(nll.size());
  std::vector<double> sorted = nll;
  std::sort(sorted.begin(), sorted.end());
  double mean = 0;
  for (double v : nll) mean += v / T;
  const double median = T % 2 ? sorted[T / 2] : 0.5 * (sorted[T / 2 - 1] + sorted[T / 2]);
  const int worst = static_cast<int>(std::max_element(nll.begin(), nll.end()) - nll.begin());
  const int best = static_cast<int>(std::min_element(nll.begin(), nll.end()) - nll.begin());
  const double q99 = prior.summary().held_out_nll_q99;
  int above = 0;
  if (std::isfinite(q99))
    above =
        static_cast<int>(std::count_if(nll.begin(), nll.end(), [&](double v) { return v > q99; }));

  if (o.json) {
    std::string j = "{\"file\": \"" + JsonEscape(o.file) + "\", \"model\": \"" +
                    JsonEscape(o.model) + "\", \"skeleton\": \"" +
                    JsonEscape(prior.skeleton().name()) + "\", \"frames\": " + std::to_string(T) +
                    ", \"fps\": " + JsonNumber(motion.fps()) +
                    ", \"unit\": \"nats per pose\", \"nll\": [";
    for (int t = 0; t < T; ++t) j += (t ? ", " : "") + JsonNumber(nll[t]);
    j += "], \"summary\": {\"mean\": " + JsonNumber(mean) + ", \"median\": " + JsonNumber(median) +
         ", \"min\": " + JsonNumber(sorted.front()) + ", \"best_frame\": " + std::to_string(best) +
         ", \"max\": " + JsonNumber(sorted.back()) + ", \"worst_frame\": " + std::to_string(worst) +
         ", \"held_out_q50\": " + JsonNumber(prior.summary().held_out_nll_q50) +
         ", \"held_out_q99\": " + JsonNumber(q99) + ", \"frames_above_held_out_q99\": " +
         (std::isfinite(q99) ? std::to_string(above) : std::string("null")) + "}}\n";
    std::fputs(j.c_str(), stdout);
    return;
  }
  std::printf("file:      %s (%d frames at %.6g Hz)\n", o.file.c_str(), T, motion.fps());
  std::printf("prior:     %s (skeleton %s, trained on %s)\n", o.model.c_str(),
              prior.skeleton().name().c_str(),
              prior.summary().protocol.empty() ? "unknown data" : prior.summary().protocol.c_str());
  if (!o.summary_only) {
    std::printf("\n%6s %12s\n", "frame", "NLL");
    for (int t = 0; t < T; ++t) {
      std::printf(
          "%6d %12.4f%s\n", t, nll[t],
          std::isfinite(q99) && nll[t] > q99 ? "  above the 99th percentile of real poses" : "");
    }
    std::printf("\n");
  }
  std::printf(
      "NLL (nats per pose; lower = more plausible): mean %.4f, median %.4f, best %.4f "
      "(frame %d), worst %.4f (frame %d)\n",
      mean, median, sorted.front(), best, sorted.back(), worst);
  if (std::isfinite(q99)) {
    std::printf(
        "real held-out poses score: median %.4f, 99th percentile %.4f; frames above it: "
        "%d of %d (%.1f%%)\n",
        prior.summary().held_out_nll_q50, q99, above, T, 100.0 * above / T);
  }
}

// ---------------------------------------------------------------------------------------------
// sample

void RunSample(const SampleOptions& o, const GlobalOptions& g) {
  FormatOfPath(o.output);  // fail on an unsupported extension before any work
  const PosePrior prior = LoadPosePrior(o.model);
  const double fps = prior.summary().fps > 0 ? prior.summary().fps : 30.0;
  const Motion poses = prior.Sample(o.count, o.seed, o.temperature, {}, fps, o.steps);
  WriteMotionFile(o.output, poses);
  std::printf(
      "wrote %s poses (skeleton %s, %d joints, metres, root at the origin, mean training "
      "bone lengths) to %s\n",
      WithThousands(o.count).c_str(), prior.skeleton().name().c_str(),
      prior.skeleton().num_joints(), o.output.c_str());
}

}  // namespace

void AddPriorCommand(CLI::App& app, GlobalOptions& global) {
  CLI::App* prior = app.add_subcommand(
      "prior", "Pose prior: a normalizing flow on limb directions that scores and samples poses");
  prior->require_subcommand(1);

  auto t = std::make_shared<TrainOptions>();
  CLI::App* train = prior->add_subcommand(
      "train", "Train a pose prior on single frames of a protocol's training split");
  train->footer(
      "A share of the training clips is held out to measure the NLL after every epoch; the test\n"
      "split is scored once at the end. A checkpoint is written to OUT after every epoch and an\n"
      "interrupted run (Ctrl-C) resumes when the same command is run again. Result: "
      "OUT/prior.yaml\n"
      "+ OUT/weights.npy (the bundle) and OUT/train_log.tsv. Threads: --threads, else\n"
      "$MOTIONFORK_THREADS, else 1.");
  train
      ->add_option("--protocol", t->protocol, "Protocol name (bandai, h36m, humaneva) or YAML path")
      ->required();
  train
      ->add_option("--data", t->data,
                   "Data folder of the protocol (see 'motionfork dataset stats')")
      ->required()
      ->check(CLI::ExistingDirectory);
  train->add_option("--out", t->out, "Output folder for the bundle and the checkpoint")->required();
  train->add_option("--config", t->config,
                    "Prior config name in configs/models/ or YAML path (default: flow_prior)");
  train->add_option("--split", t->split_file, "Split file overriding the protocol's split.file");
  train
      ->add_option("--threads", t->threads,
                   "LibTorch/BLAS threads (default $MOTIONFORK_THREADS or 1)")
      ->check(CLI::PositiveNumber);
  train->add_flag("--restart", t->restart,
                  "Discard a checkpoint or trained prior in OUT and train from the start");
  train->callback([t, &global] { RunTrain(*t, global); });

  auto s = std::make_shared<ScoreOptions>();
  CLI::App* score = prior->add_subcommand(
      "score", "Per-frame negative log-likelihood of a motion under a prior, and a summary");
  score->footer(
      "NLL is in nats per pose; lower = more plausible. The summary compares the frames with what\n"
      "real held-out poses scored in training (frames above their 99th percentile are flagged).\n"
      "The motion is put on the prior's skeleton: by joint names, by index (.npy), or through the\n"
      "skeleton config the prior was trained with (e.g. a 22-joint Bandai BVH).");
  score->add_option("MOTION", s->file, "Motion file (.bvh, .npy, .csv)")
      ->required()
      ->check(CLI::ExistingFile);
  score->add_option("--model", s->model, "Prior bundle folder (holding prior.yaml)")->required();
  AddMotionInputOptions(score, &s->input);
  score->add_flag("--json", s->json, "Print one JSON object (per-frame NLL and the summary)");
  score->add_flag("--summary-only", s->summary_only, "Text output without the per-frame table");
  score->callback([s, &global] { RunScore(*s, global); });

  auto m = std::make_shared<SampleOptions>();
  CLI::App* sample = prior->add_subcommand("sample", "Draw poses from a prior into a motion file");
  sample->footer(
      "Poses come from the prior's density on valid poses (unit limb directions): flow samples\n"
      "normalised, then Metropolis-Hastings steps (--steps) that move them to where the prior "
      "puts\n"
      "real poses. One pose per frame, root at the origin, the training data's mean bone lengths,\n"
      "at the protocol's frame rate.");
  sample->add_option("--model", m->model, "Prior bundle folder (holding prior.yaml)")->required();
  sample->add_option("-n,--count", m->count, "Number of poses")
      ->required()
      ->check(CLI::PositiveNumber);
  sample->add_option("-o,--out", m->output, "Output file (.npy [N, J, 3] or .csv; required)");
  AddDeprecatedOption(sample, "--output", "-o/--out", &m->output);
  sample->add_option("--seed", m->seed, "Random seed (default 0)");
  sample
      ->add_option("--temperature", m->temperature,
                   "Sample p^(1/T) (default 1; < 1 gives more typical poses)")
      ->check(CLI::PositiveNumber);
  sample
      ->add_option("--steps", m->steps,
                   "Metropolis-Hastings steps (default 1000; 0 = raw flow samples, fast but mostly "
                   "implausible)")
      ->check(CLI::NonNegativeNumber);
  sample->callback([m, &global] {
    RequireArgument(m->output, "-o,--out");
    RunSample(*m, global);
  });
}

}  // namespace motionfork::app
