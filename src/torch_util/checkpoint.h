// Training checkpoints (LibTorch): a module's weights, its optimiser's state and the number of
// epochs done, in one folder, each file written all-or-nothing; the epoch count is written last,
// so a folder is either a complete checkpoint or an older complete one.
#pragma once

#include <torch/torch.h>

#include <string>

namespace motionfork {

// Writes DIR/<weights_name>, DIR/optimizer.pt and then DIR/state.pt (epochs_done).
void SaveCheckpoint(const std::string& dir, const std::string& weights_name,
                    torch::nn::Module& module, torch::optim::Optimizer& optimizer, int epochs_done);

// Loads a checkpoint written by SaveCheckpoint into module and optimizer and returns its epoch
// count; returns 0 (and loads nothing) when DIR/state.pt does not exist.
int LoadCheckpoint(const std::string& dir, const std::string& weights_name,
                   torch::nn::Module& module, torch::optim::Optimizer& optimizer);

}  // namespace motionfork
