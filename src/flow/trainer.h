// Training the pose prior: negative log-likelihood of single frames, Adam, GSPS's learning-rate
// schedule, held-out NLL after every epoch, a checkpoint after every epoch, resume.
//
// Deterministic: the same config (seed), data and thread count give bit-identical weights,
// whether the run was interrupted and resumed or not (each epoch's frame order is derived from
// the seed and the epoch number; the checkpoint holds the weights and Adam's state).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "flow/pose_prior.h"
#include "flow/prior_data.h"

namespace motionfork {

struct PriorTrainProgress {
  int epoch = 0;     // running epoch, 0-based
  int epochs = 0;    // total
  int64_t step = 0;  // steps done in this epoch
  int64_t steps_per_epoch = 0;
  double learning_rate = 0;  // this epoch's
  double train_nll = 0;      // mean NLL over this epoch's frames so far, nats per pose
  bool epoch_done = false;   // true once per epoch: held_out_nll set, checkpoint written
  double held_out_nll = 0;   // after the epoch (NaN without held-out frames)
  double epoch_seconds = 0;  // wall time of this epoch so far
};

struct PriorTrainCallbacks {
  // Called after every step and once more when an epoch is done. May be empty.
  std::function<void(const PriorTrainProgress&)> progress;
  // Polled after every step; returning true stops training (the last checkpoint stays; the
  // unfinished epoch is redone on resume). May be empty.
  std::function<bool()> stop_requested;
};

struct PriorTrainOutcome {
  bool completed = false;      // every epoch done (false: stopped on request)
  int resumed_from_epoch = 0;  // epochs the checkpoint already held (0 = fresh start)
  int epochs = 0;              // the run's epochs (MakePriorSchedule: raised to min_steps)
  bool epochs_raised = false;  // the config's epochs gave fewer than min_steps steps
  // Completed with the held-out NLL still falling (HeldOutStillFalling): train longer.
  bool still_falling = false;
  double recent_gain = 0;  // nats the last tenth of the epochs gained on the best before them
};

// Whether a run ended before its held-out NLL stopped falling: the last epoch's NLL is more than
// kPriorStillFallingNats below the best of the epochs before the last tenth of the run (at least
// 2 epochs). gain: that difference (0 when too few epochs).
constexpr double kPriorStillFallingNats = 0.1;
bool HeldOutStillFalling(const std::vector<double>& held_out_nll, double* gain = nullptr);

// The learning rate of an epoch (0-based) under GSPS's schedule (see PriorTrainOptions).
double PriorLearningRate(const PriorTrainOptions& options, int epoch);

// Trains `prior` in place with prior.config().training on data.train, measuring data.held_out
// after every epoch. checkpoint_path: "" = no checkpoints; otherwise the state is written there
// (all-or-nothing) after every epoch, and an existing checkpoint is resumed. A checkpoint written
// with another config or other data is refused (std::invalid_argument saying which differs);
// an unreadable one is a FormatError. On completion the prior's summary holds the per-epoch NLLs,
// held-out quantiles, test NLL (data.test), frame counts and the accumulated wall time, and its
// bone lengths are data.bone_lengths. Throws std::runtime_error if the loss becomes non-finite.
PriorTrainOutcome TrainPosePrior(PosePrior& prior, const PriorData& data,
                                 const std::string& checkpoint_path,
                                 const PriorTrainCallbacks& callbacks = {});

// Mean NLL (nats per pose) of frames under a prior; NaN for no frames.
double MeanNll(const PosePrior& prior, const PriorFrames& frames);

}  // namespace motionfork
