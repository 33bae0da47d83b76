#include "pipeline/prior_training.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "bundle/prior_bundle.h"
#include "config/config_paths.h"
#include "config/protocol_dataset.h"
#include "dataset/dataset.h"
#include "io/file_util.h"
#include "launch/worker_place.h"

namespace motionfork::pipeline {
namespace {

namespace fs = std::filesystem;

std::string Fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

std::string TrainLog(const PriorTrainingSummary& y, const PriorTrainOptions& t) {
  std::string log = "epoch\tlearning_rate\ttrain_nll\theld_out_nll\n";
  for (size_t e = 0; e < y.train_nll.size(); ++e) {
    log += std::to_string(e + 1) + "\t" + Fmt("%.6g", PriorLearningRate(t, static_cast<int>(e))) +
           "\t" + Fmt("%.6f", y.train_nll[e]) + "\t" + Fmt("%.6f", y.held_out_nll[e]) + "\n";
  }
  return log;
}

}  // namespace

PriorTrainingRun TrainPriorBundle(const PriorTrainingRequest& o,
                                  const PriorTrainingCallbacks& callbacks) {
  const std::string config_path = ResolveConfigPath(o.config_dir, "models", o.config);
  const PriorConfig config = LoadFlowConfig(config_path);
  const fs::path out(o.out);
  PriorTrainingRun run;
  run.checkpoint = (out / "checkpoint.pt").string();
  const bool writes = IsRankZero();  // rank 0 alone reads and writes the run's files
  if (writes && o.restart) {
    std::error_code ec;
    fs::remove(run.checkpoint, ec);
  } else if (writes && !fs::exists(run.checkpoint) && fs::exists(out / "prior.yaml")) {
    throw std::invalid_argument(
        o.out +
        " already holds a trained prior (prior.yaml) and no checkpoint to resume: pass "
        "--restart to train it again, or choose another --out");
  }
  ProtocolOptions protocol;
  SkeletonConfig skeleton;
  PriorData data;
  {  // the clips are freed once their frames are sampled
    const Dataset ds = LoadProtocolDataset(
        {o.protocol, o.data, o.split_file, o.config_dir, o.cache_dir}, callbacks.loading);
    protocol = ds.protocol;
    skeleton = ds.skeleton;
    data = MakePriorData(ds, config.training);
  }
  PosePrior prior(skeleton.skeleton, config);
  prior.set_skeleton_config(protocol.skeleton);
  prior.mutable_summary().protocol = protocol.name;
  prior.mutable_summary().fps = protocol.fps;
  prior.mutable_summary().threads = o.threads;
  if (callbacks.started) callbacks.started(prior, data, config_path);
  if (writes) fs::create_directories(out);
  run.outcome = TrainPosePrior(prior, data, run.checkpoint, callbacks.training);
  run.completed = run.outcome.completed;
  if (!run.completed) return run;
  run.summary = prior.summary();
  if (!writes) return run;
  SavePosePrior(prior, o.out);
  WriteFileAtomically((out / "train_log.tsv").string(), TrainLog(run.summary, config.training));
  std::error_code ec;
  fs::remove(run.checkpoint, ec);  // the bundle holds everything; a re-run must say --restart
  return run;
}

}  // namespace motionfork::pipeline
