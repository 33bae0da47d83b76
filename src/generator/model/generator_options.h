// Generator settings: the network's sizes (GeneratorOptions) and what a saved generator is
// (ModelConfig, a bundle's model.yaml). Plain structs, no LibTorch and no YAML: the bundle layer
// (bundle/generator_bundle.h) reads and writes them; configs, apps and the API read them.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "core/skeleton.h"

namespace motionfork {

struct GeneratorOptions {
  int num_nodes = 0;  // graph nodes = joints without the root (16 for 17-joint skeletons)
  int t_his = 0;      // history frames
  int t_pred = 0;     // future frames
  int n_pre = 10;     // DCT coefficients kept of t_his + t_pred (GSPS code: 10 H36M, 8 HumanEva)
  int hidden = 256;   // graph-conv feature width
  int blocks = 4;     // residual blocks of two graph-convs each
  int nz = 64;        // latent size per body part
  bool batch_norm = true;             // batch normalisation after each inner graph-conv (GSPS code)
  double dropout = 0.0;               // dropout after each inner activation (training only)
  std::string partition = "default";  // the skeleton's body-part partition, in prediction order
  // "": the network sees poses in the data's axes. An up axis ("y", "z"): it sees each window in
  // the body's own frame, turned about that axis so that its last history frame faces one way
  // (core/heading.h; issue 27), and what it predicts is turned back.
  std::string body_frame;

  int num_frames() const { return t_his + t_pred; }
  int coeff_features() const { return 3 * n_pre; }  // per node: x, y, z of each coefficient
};

// Upper bounds on a generator's sizes (ValidateGeneratorOptions): far above any published model,
// low enough that a damaged model.yaml cannot make the loader allocate more than ~1 GB.
constexpr int kMaxGeneratorNodes = 1000;
constexpr int kMaxGeneratorFrames = 4096;                 // t_his + t_pred
constexpr int kMaxGeneratorWidth = 4096;                  // hidden, nz
constexpr int kMaxGeneratorBlocks = 100;                  // residual blocks
constexpr int64_t kMaxGeneratorPartWeights = 64ll << 20;  // (2 blocks + 2) hidden^2 per part

// Throws std::invalid_argument naming the field, its value and the rule.
void ValidateGeneratorOptions(const GeneratorOptions& o);

constexpr const char* kGeneratorBundleFormat = "motionfork-generator-1";

// A bundle's model.yaml: protocol settings, network sizes, skeleton with its parts, so that a
// bundle describes itself.
struct ModelConfig {
  std::string format = kGeneratorBundleFormat;
  std::string protocol;                     // protocol name the model was trained under
  double fps = 0;                           // Hz
  GeneratorOptions generator;               // includes t_his, t_pred, num_nodes, partition
  SkeletonSpec skeleton;                    // the protocol skeleton, parts as joint lists
  std::map<std::string, std::string> info;  // free-form provenance (command, seed, epochs, ...)
};

}  // namespace motionfork
