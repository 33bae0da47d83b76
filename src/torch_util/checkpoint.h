// Training checkpoints (LibTorch): a module's weights, its optimiser's state, the number of
// epochs done and any extra state of the training loop, in one folder, written as one set
// (io/file_util.h WriteFileSet): a folder is either the complete new checkpoint or the complete
// old one, also when a write is killed half-way.
#pragma once

#include <torch/torch.h>

#include <string>
#include <utility>
#include <vector>

namespace motionfork {

// Writes DIR/<weights_name>, DIR/optimizer.pt, DIR/state.pt (epochs_done) and `extra_files`
// (name -> bytes, e.g. a training loop's own state) all-or-nothing.
void SaveCheckpoint(const std::string& dir, const std::string& weights_name,
                    torch::nn::Module& module, torch::optim::Optimizer& optimizer, int epochs_done,
                    const std::vector<std::pair<std::string, std::string>>& extra_files = {});

// Loads a checkpoint written by SaveCheckpoint into module and optimizer and returns its epoch
// count; returns 0 (and loads nothing) when DIR/state.pt does not exist. A write to DIR killed
// half-way is rolled back first.
int LoadCheckpoint(const std::string& dir, const std::string& weights_name,
                   torch::nn::Module& module, torch::optim::Optimizer& optimizer);

}  // namespace motionfork
