// Issue 30: which hidden layers of the shipped Bandai generator may run their products in bf16
// while every future stays within 1 mm of float32's, chosen on VALIDATION windows (every 10th
// training clip; never the test split), and the time of 50 futures of one history for each choice
// (in turns with float32). FusedGenerator's kBf16 runs the choice made here ("each part's second
// half"); a third argument `test` confirms it on the test split's windows.
//   bench_bf16_layer_mask ../shared/data/bandai models/bandai [test]
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bundle/generator_net_bundle.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"
#include "eval/test_set.h"
#include "generator/inference/fused_generator.h"
#include "generator/kernels/bf16_product.h"
#include "generator/model/generator_net.h"

using namespace motionfork;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_bf16_layer_mask BANDAI_DIR MODEL_DIR [test]\n");
    return 2;
  }
  if (!kernels::Bf16KernelRuns()) {
    std::printf("no AVX512-BF16 here\n");
    return 0;
  }
  torch::set_num_threads(1);
  const std::string config_dir = MOTIONFORK_BENCH_CONFIG_DIR;
  const ProtocolOptions p =
      LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", "bandai"));
  const SkeletonConfig s =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", p.skeleton));
  DatasetLoadOptions load;
  const Dataset ds = LoadDataset(p, s, argv[1], load);
  // argv[3] == "test": the test split's clips instead (to confirm a choice made on validation).
  const bool on_test = argc > 3 && std::string(argv[3]) == "test";
  std::vector<const Clip*> validation;
  const std::vector<int> train = ds.ClipIndices(on_test ? Split::kTest : Split::kTrain);
  for (size_t i = 0; i < train.size(); i += on_test ? 1 : 10)
    validation.push_back(&ds.clips[train[i]]);
  const TestSet ts = BuildTestSet(validation, p);
  ModelConfig config;
  GeneratorNet net = LoadGeneratorBundle(argv[2], &config);
  net->eval();
  const GeneratorOptions& g = config.generator;
  const int64_t N = g.num_nodes, J = N + 1, K = 50;
  const int hidden = static_cast<int>(net->num_parts()) * 2 * g.blocks;
  std::printf("%s: %d windows from %zu clips; %d hidden layers\n",
              on_test ? "test split" : "validation", ts.num_windows(), validation.size(), hidden);

  const int stride = std::max(1, ts.num_windows() / 400);
  std::vector<std::vector<float>> histories;
  for (int w = 0; w < ts.num_windows(); w += stride) {
    const float* x = ts.history(w);
    std::vector<float> h(static_cast<size_t>(g.t_his) * N * 3);
    for (int t = 0; t < g.t_his; ++t)
      for (int64_t j = 1; j < J; ++j)
        for (int a = 0; a < 3; ++a)
          h[(t * N + j - 1) * 3 + a] = x[(t * J + j) * 3 + a] - x[(t * J) * 3 + a];
    histories.push_back(std::move(h));
  }
  torch::manual_seed(0);
  std::vector<std::vector<torch::Tensor>> latents;
  for (size_t w = 0; w < histories.size(); ++w) {
    std::vector<torch::Tensor> z;
    for (int64_t part = 0; part < net->num_parts(); ++part)
      z.push_back(torch::randn({K, g.nz}).contiguous());
    latents.push_back(z);
  }
  const FusedGenerator fp32(*net);
  const size_t out_size = static_cast<size_t>(K) * g.t_pred * N * 3;
  std::vector<std::vector<float>> reference(histories.size(), std::vector<float>(out_size));
  auto run = [&](const FusedGenerator& f, size_t w, float* out) {
    std::vector<const float*> z;
    for (const torch::Tensor& t : latents[w]) z.push_back(t.data_ptr<float>());
    f.Predict(histories[w].data(), 1, K, z, {}, out);
  };
  for (size_t w = 0; w < histories.size(); ++w) run(fp32, w, reference[w].data());

  struct Mask {
    std::string name;
    std::vector<bool> layers;
  };
  const int per_part = 2 * g.blocks;
  auto make = [&](const std::string& name, auto keep) {
    Mask m{name, std::vector<bool>(hidden)};
    for (int l = 0; l < hidden; ++l) m.layers[l] = keep(l / per_part, l % per_part);
    return m;
  };
  const std::vector<Mask> masks = {
      make("all hidden layers", [](int, int) { return true; }),
      make("part 0 only", [](int part, int) { return part == 0; }),
      make("part 1 only", [](int part, int) { return part == 1; }),
      make("all but each part's first", [](int, int i) { return i > 0; }),
      make("all but each part's last", [&](int, int i) { return i < per_part - 1; }),
      make("all but each part's first and last",
           [&](int, int i) { return i > 0 && i < per_part - 1; }),
      make("each part's first half", [&](int, int i) { return i < per_part / 2; }),
      make("each part's second half", [&](int, int i) { return i >= per_part / 2; }),
      {"kBf16 as shipped (no mask given)", {}},
  };
  std::vector<float> out(out_size);
  auto time_of = [&](const FusedGenerator& f) {
    std::vector<double> t;
    for (int r = 0; r < 41; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      run(f, r % histories.size(), out.data());
      t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
  };
  std::printf("%-36s %9s %9s %9s %9s %9s\n", "bf16 layers", "mean mm", "worst mm", "ms", "fp32 ms",
              "speed-up");
  for (const Mask& m : masks) {
    const FusedGenerator f(*net, ProductPrecision::kBf16, m.layers);
    double sum = 0, worst = 0;
    int64_t futures = 0;
    for (size_t w = 0; w < histories.size(); ++w) {
      run(f, w, out.data());
      const size_t per_future = static_cast<size_t>(g.t_pred) * N;
      for (int64_t k = 0; k < K; ++k) {
        double d = 0;
        for (size_t j = 0; j < per_future; ++j) {
          const size_t i = (k * per_future + j) * 3;
          const float* a = reference[w].data() + i;
          const float* b = out.data() + i;
          d += 1e3 * std::sqrt(std::pow(a[0] - b[0], 2) + std::pow(a[1] - b[1], 2) +
                               std::pow(a[2] - b[2], 2));
        }
        d /= static_cast<double>(per_future);
        sum += d;
        worst = std::max(worst, d);
        ++futures;
      }
    }
    const double t32 = time_of(fp32), t16 = time_of(f), t32b = time_of(fp32);
    const double base = 0.5 * (t32 + t32b);
    std::printf("%-36s %9.4f %9.4f %9.2f %9.2f %9.2fx\n", m.name.c_str(), sum / futures, worst,
                t16 * 1e3, base * 1e3, base / t16);
    std::fflush(stdout);
  }
  return 0;
}
