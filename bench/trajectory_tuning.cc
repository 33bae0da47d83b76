// Issue 27: the trajectory network's settings, chosen on VALIDATION windows (every
// `validation_every`-th training clip; never the test split): trains it from a model config's
// `trajectory` section (generator.body_frame: true) on the Bandai training split into OUT and
// prints each epoch's losses and validation root ADE / FDE. The generator's weights are not
// needed (the network learns from the true poses), so settings can be tried while it trains.
//   bench_trajectory_tuning ../shared/data/bandai configs/models/bandai.yaml OUT
#include <cstdio>
#include <string>

#include "bundle/generator_bundle.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/rig_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"
#include "generator/training/training_manifest.h"
#include "generator/training/trajectory_training.h"

using namespace motionfork;

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: bench_trajectory_tuning BANDAI_DIR MODEL_CONFIG OUT\n");
    return 2;
  }
  torch::set_num_threads(1);
  const std::string config_dir = MOTIONFORK_BENCH_CONFIG_DIR;
  const GeneratorTrainConfig cfg = LoadGeneratorTrainConfig(argv[2]);
  if (!cfg.trajectory) {
    std::fprintf(stderr, "%s has no trajectory section\n", argv[2]);
    return 2;
  }
  const ProtocolOptions p =
      LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", cfg.protocol));
  const SkeletonConfig s =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", p.skeleton));
  const Dataset ds = LoadDataset(p, s, argv[1], DatasetLoadOptions{});
  const Skeleton& skeleton = *ds.skeleton.skeleton;
  const ModelConfig model = TrainingModelConfig(cfg, ds.protocol, skeleton, "");
  const std::vector<int> feet = AnkleJoints(skeleton, config_dir);
  TrainCallbacks cb;
  cb.epoch = [](int epoch, const std::vector<std::pair<std::string, double>>& terms, double sec) {
    std::printf("epoch %3d %5.1f s", epoch + 1, sec);
    for (const auto& [name, v] : terms) std::printf("  %s %.4f", name.c_str(), v);
    std::printf("\n");
    std::fflush(stdout);
  };
  const TrajectoryTrainSummary sum = TrainTrajectory(*cfg.trajectory, model, ds, feet, argv[3], cb);
  std::printf("%s", TrajectoryDoneText(sum, argv[3]).c_str());
  return 0;
}
