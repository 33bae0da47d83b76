// GSPS's Human3.6M generator sizes, shared by the generator benchmarks: t_his 25, t_pred 100,
// n_pre 10, hidden 256, 4 residual blocks, nz 64, and 16 nodes unless told (17 joints less the
// root).
#pragma once

#include <cstdint>
#include <vector>

#include "generator/model/generator_options.h"

namespace motionfork::bench {

inline GeneratorOptions H36mGeneratorOptions(int64_t nodes = 16) {
  GeneratorOptions o;
  o.num_nodes = nodes;
  o.t_his = 25;
  o.t_pred = 100;
  o.n_pre = 10;
  o.hidden = 256;
  o.blocks = 4;
  o.nz = 64;
  return o;
}

// Multiply-adds of the residual blocks' H x H products per sample and pass, all parts: what the
// bf16 engines run (issue 30).
inline double HiddenProductMacsPerSample(const GeneratorOptions& o, int parts) {
  return parts * 2.0 * o.blocks * o.num_nodes * o.hidden * o.hidden;
}

// Multiply-adds of one generator pass per sample (graph-conv products only), all parts.
inline double MacsPerSample(const GeneratorOptions& o, int parts) {
  const double N = o.num_nodes, C = o.coeff_features(), H = o.hidden, Z = o.nz;
  const double input = N * C * H + Z * H + N * N * H;
  const double hidden = HiddenProductMacsPerSample(o, 1) + 2 * o.blocks * N * N * H;
  const double output = N * H * C + N * N * C;
  return parts * (input + hidden + output);
}

// Two parts of the 16 nodes (the first six, the other ten), as bench_generator has always run.
inline std::vector<std::vector<int64_t>> TwoParts16() {
  return {{0, 1, 2, 3, 4, 5}, {6, 7, 8, 9, 10, 11, 12, 13, 14, 15}};
}

}  // namespace motionfork::bench
