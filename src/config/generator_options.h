// Sizes of the GSPS-style generator. No LibTorch here: configs, apps and bundles read this.
#pragma once

#include <string>

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

  int num_frames() const { return t_his + t_pred; }
  int coeff_features() const { return 3 * n_pre; }  // per node: x, y, z of each coefficient
};

// Throws std::invalid_argument naming the field, its value and the rule.
void ValidateGeneratorOptions(const GeneratorOptions& o);

}  // namespace motionfork
