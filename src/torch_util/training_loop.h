// What the training loops share (the generator's, the HG-VAE's, the Motion-DVAE's training and
// fine-tuning): resuming from OUT/checkpoint, the non-finite loss check, the
// learning rate and KL weight schedules, the epoch log OUT/log.csv. The optimiser step, over one
// worker or many, is DataParallelStep (data_parallel.h).
#pragma once

#include <torch/torch.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace motionfork {

// Creates ckpt_dir and loads the checkpoint in it into module and optimizer (checkpoint.h): the
// epochs it had done, 0 when there is none (a fresh start). The epoch log (AppendEpochLog) is cut
// back to those epochs: a run killed between an epoch's log row and its checkpoint leaves no row
// without its checkpoint.
int ResumeFromCheckpoint(const std::filesystem::path& ckpt_dir, const std::string& weights_name,
                         torch::nn::Module& module, torch::optim::Optimizer& optimizer,
                         const std::filesystem::path& epoch_log);

// ResumeFromCheckpoint, telling `message` (when set) "resuming from <ckpt_dir> after epoch <N>"
// when there was a checkpoint.
int ResumeTraining(const std::filesystem::path& ckpt_dir, const std::string& weights_name,
                   torch::nn::Module& module, torch::optim::Optimizer& optimizer,
                   const std::filesystem::path& epoch_log,
                   const std::function<void(const std::string&)>& message);

// Keeps the header and the rows of epochs 1..epochs_done of an epoch log (all-or-nothing); nothing
// happens when the file does not exist.
void TrimEpochLog(const std::filesystem::path& file, int epochs_done);

// Throws std::runtime_error "<what>: the loss became non-finite at epoch <epoch + 1>" when loss is
// NaN or infinite (epoch 0-based).
void RequireFiniteLoss(double loss, const std::string& what, int epoch);

// Every parameter group of adam at learning rate lr.
void SetLearningRate(torch::optim::Adam& adam, double lr);

// A weight rising linearly from start to 1 over the first `epochs` epochs (progress: epochs done,
// fractional), then 1; always 1 when epochs <= 0.
double AnnealedWeight(double start, int epochs, double progress);

double SecondsSince(std::chrono::steady_clock::time_point start);

// Appends an epoch's row to a training log (OUT/log.csv): `epoch,<column>,seconds,<terms...>` with
// the header first when the file does not exist yet; epoch is 0-based, the row says epoch + 1.
void AppendEpochLog(const std::filesystem::path& file, const std::string& column, int epoch,
                    double value, double seconds,
                    const std::vector<std::pair<std::string, double>>& terms);

}  // namespace motionfork
