#include "pipeline/prior_training_text.h"

#include <algorithm>
#include <cmath>

#include "core/text_format.h"
#include "flow/trainer.h"

namespace motionfork::pipeline {

std::string PriorTrainingStartText(const PosePrior& prior, const PriorData& data,
                                   const std::string& config_path, const PriorTrainingRequest& o) {
  std::string s;
  const PriorTrainOptions& t = prior.config().training;
  StringAppendf(
      &s, "prior:     %d layers, %d reflections each, %s parameters, %d numbers per pose (%s)\n",
      prior.config().model.num_layers, prior.config().model.num_reflections,
      WithThousands(prior.num_parameters()).c_str(), prior.dim(), config_path.c_str());
  StringAppendf(&s,
                "data:      %s, protocol %s: train %s frames (%s clips), held-out %s frames (%s "
                "training clips, %.0f%%), test %s frames",
                o.data.c_str(), prior.summary().protocol.c_str(),
                WithThousands(data.train.size()).c_str(), WithThousands(data.train_clips).c_str(),
                WithThousands(data.held_out.size()).c_str(),
                WithThousands(static_cast<long long>(data.held_out_clips.size())).c_str(),
                100 * t.held_out_share, WithThousands(data.test.size()).c_str());
  if (t.frame_stride > 1) StringAppendf(&s, ", every %d-th frame", t.frame_stride);
  if (data.dropped_frames > 0) {
    StringAppendf(&s, ", %s frames skipped (zero-length bone)",
                  WithThousands(data.dropped_frames).c_str());
  }
  const int64_t batch = std::min<int64_t>(t.batch_size, std::max<int64_t>(1, data.train.size()));
  const int64_t steps = (data.train.size() + batch - 1) / batch;
  const PriorSchedule run = MakePriorSchedule(t, steps);
  StringAppendf(
      &s,
      "\ntraining:  %d epochs of %s step%s, batch %d, Adam lr %g (constant %d epochs, then "
      "linear), weight decay %g, seed %llu, %d thread%s\n",
      run.epochs, WithThousands(steps).c_str(), steps == 1 ? "" : "s", t.batch_size,
      t.learning_rate, run.constant_epochs, t.weight_decay, static_cast<unsigned long long>(t.seed),
      o.threads, o.threads == 1 ? "" : "s");
  if (run.raised) {
    StringAppendf(&s,
                  "           (the config's %d epochs are %s steps on this data: raised to reach "
                  "training.min_steps %s)\n",
                  t.epochs, WithThousands(static_cast<int64_t>(t.epochs) * steps).c_str(),
                  WithThousands(t.min_steps).c_str());
  }
  return s;
}

std::string PriorEpochText(const PriorTrainProgress& p) {
  return StringPrintf("epoch %2d/%d  lr %.2e  train NLL %9.4f  held-out NLL %9.4f  (%s)\n",
                      p.epoch + 1, p.epochs, p.learning_rate, p.train_nll, p.held_out_nll,
                      Duration(p.epoch_seconds).c_str());
}

bool PriorEpochGetsLine(int epoch, int epochs) {
  if (epochs <= kPriorEpochLines || epoch == 0 || epoch + 1 >= epochs) return true;
  const int every = (epochs + kPriorEpochLines - 1) / kPriorEpochLines;
  return (epoch + 1) % every == 0;
}

std::string PriorTrainingDoneText(const PriorTrainingRun& run, const std::string& out) {
  const PriorTrainingSummary& y = run.summary;
  std::string s;
  StringAppendf(&s,
                "done:      held-out NLL %.4f (median %.4f, 99th percentile %.4f), test NLL %.4f "
                "nats per pose; %s of training\n",
                y.held_out_nll.empty() ? std::nan("") : y.held_out_nll.back(), y.held_out_nll_q50,
                y.held_out_nll_q99, y.test_nll, Duration(y.seconds).c_str());
  StringAppendf(&s, "bundle:    %s (prior.yaml, weights.npy, train_log.tsv)\n", out.c_str());
  if (run.outcome.still_falling) {
    StringAppendf(&s,
                  "warning:   the held-out NLL was still falling (%.2f nats below the best before "
                  "the last tenth of the epochs): train longer (training.min_steps or "
                  "training.epochs, --restart)\n",
                  run.outcome.recent_gain);
  }
  return s;
}

std::string PriorTrainingInterruptedText(const std::string& out) {
  return StringPrintf(
      "interrupted: the checkpoint in %s keeps every finished epoch; run the same command to "
      "resume\n",
      out.c_str());
}

}  // namespace motionfork::pipeline
