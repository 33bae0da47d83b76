#include "tiny_bundle.h"

#include "bodyparts/part_plan.h"
#include "bundle/generator_net_bundle.h"
#include "config/config_paths.h"
#include "config/skeleton_config.h"
#include "test_support.h"

namespace motionfork::testing {

void WriteTinyBundle(const std::string& dir, const std::string& config_dir, uint64_t seed) {
  const SkeletonConfig sc =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", "bandai"));
  ModelConfig m;
  m.protocol = "bandai";
  m.fps = 30;
  GeneratorOptions& g = m.generator;
  g.num_nodes = sc.skeleton->num_joints() - 1;
  g.t_his = 5;
  g.t_pred = 10;
  g.n_pre = 6;
  g.hidden = 16;
  g.blocks = 1;
  g.nz = 4;
  m.skeleton = sc.skeleton->ToSpec();
  m.info["config"] = "tiny (tests/api/tiny_bundle.cc, untrained)";
  torch::manual_seed(seed);
  GeneratorNet net(g, MakePartPlan(*sc.skeleton, g.partition).nodes);
  net->eval();
  SaveGeneratorBundle(dir, m, net);
}

Motion TinyBundleHistory(int frames, double fps) { return MakeWalkingMotion(frames, fps, 3); }

}  // namespace motionfork::testing
