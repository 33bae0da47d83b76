// The trajectory network's settings (a generator bundle's trajectory/trajectory.yaml). Plain
// struct, no LibTorch and no YAML: bundle/trajectory_bundle.h reads and writes it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace motionfork {

struct TrajectoryOptions {
  int t_his = 0, t_pred = 0;  // frames, as the generator's
  int num_nodes = 0;          // the generator's nodes (joints without the root)
  // The nodes whose future the network reads (the generator's first part, the legs): every other
  // node is read over the history only, so futures that share those nodes share their trajectory.
  std::vector<int64_t> future_nodes;
  int n_in = 8;          // DCT coefficients of the poses over t_his + t_pred frames
  int n_out = 10;        // DCT coefficients of the root's step per frame over t_pred frames
  int hidden = 512;      // width of the hidden layers
  int layers = 3;        // hidden layers
  std::string up = "y";  // the up axis of the body frame the network works in

  int num_frames() const { return t_his + t_pred; }
  // Inputs: the poses' coefficients, then the history root's steps (t_his - 1 frames x 3).
  int input_size() const { return n_in * num_nodes * 3 + (t_his - 1) * 3; }
};

// Upper bounds (ValidateTrajectoryOptions): far above a useful network, low enough that a damaged
// manifest cannot make the loader allocate more than ~1 GB.
constexpr int kMaxTrajectoryWidth = 8192;
constexpr int kMaxTrajectoryLayers = 64;

// Throws std::invalid_argument naming the field, its value and the rule.
void ValidateTrajectoryOptions(const TrajectoryOptions& o);

constexpr const char* kTrajectoryBundleFormat = "motionfork-trajectory-1";

}  // namespace motionfork
