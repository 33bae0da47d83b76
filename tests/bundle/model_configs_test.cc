// The shipped generator configs (configs/models/): each parses, names a protocol, constraint set
// and skeleton that exist, and carries GSPS's published settings for its dataset.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "bundle/generator_bundle.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "test_support.h"

using namespace motionfork;

namespace {

GeneratorTrainConfig Shipped(const std::string& name) {
  return LoadGeneratorTrainConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "models", name));
}

}  // namespace

TEST_CASE("the shipped model configs carry GSPS's settings for their datasets") {
  for (const std::string name : {"bandai", "humaneva", "h36m"}) {
    INFO(name);
    const GeneratorTrainConfig c = Shipped(name);
    CHECK(c.name == name);
    CHECK(c.protocol == name);
    CHECK(c.constraints == name);
    CHECK(std::filesystem::exists(
        ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "constraints", c.constraints)));
    const ProtocolOptions p =
        LoadProtocolConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "protocols", c.protocol));
    CHECK(p.name == name);
    CHECK(c.prior == "models/prior-" + name);
    CHECK(c.generator.hidden == 256);
    CHECK(c.generator.blocks == 4);
    CHECK(c.generator.nz == 64);
    CHECK(c.losses.past_reconstruction == 100);
    CHECK(c.losses.limb_length == 500);
    CHECK(c.losses.best_of_many == 2);
    CHECK(c.losses.multimodal == 1);
    CHECK(c.losses.prior_nll == 0.01);
    CHECK(c.losses.angle == 100);
  }
  const GeneratorTrainConfig h = Shipped("h36m");
  CHECK(h.generator.n_pre == 10);
  CHECK(h.losses.diversity == std::vector<double>{8, 25});
  CHECK(h.losses.diversity_scale == std::vector<double>{100, 300});
  for (const std::string name : {"humaneva", "bandai"}) {
    const GeneratorTrainConfig e = Shipped(name);
    CHECK(e.generator.n_pre == 8);
    CHECK(e.losses.diversity == std::vector<double>{5, 10});
    CHECK(e.losses.diversity_scale == std::vector<double>{15, 50});
  }
}

TEST_CASE("a config's body frame and trajectory section parse; a trajectory alone is refused") {
  testing::TempDir dir;
  const auto path = (dir.path() / "walker.yaml").string();
  const std::string head = "name: walker\nprotocol: bandai\ngenerator:\n  n_pre: 8\n";
  std::ofstream(path) << head
                      << "  body_frame: true\ntrajectory:\n  hidden: 64\n  epochs: 7\n"
                         "  lr_constant_epochs: 3\n  skating_weight: 0.5\n";
  const GeneratorTrainConfig c = LoadGeneratorTrainConfig(path);
  CHECK(c.body_frame);
  REQUIRE(c.trajectory);
  CHECK(c.trajectory->hidden == 64);
  CHECK(c.trajectory->epochs == 7);
  CHECK(c.trajectory->skating_weight == 0.5);
  CHECK(c.trajectory->n_out == TrajectoryTrainOptions{}.n_out);  // defaults stay
  CHECK_FALSE(c.multimodal.body_frame);  // pseudo futures matched in the data's axes, as GSPS
  std::ofstream(path) << head << "  body_frame: true\nmultimodal:\n  body_frame: true\n";
  CHECK(LoadGeneratorTrainConfig(path).multimodal.body_frame);
  std::ofstream(path) << head << "multimodal:\n  body_frame: true\n";
  CHECK_THROWS_WITH(LoadGeneratorTrainConfig(path),
                    Catch::Contains("multimodal.body_frame needs generator.body_frame"));
  std::ofstream(path) << head << "trajectory:\n  hidden: 64\n";
  CHECK_THROWS_WITH(LoadGeneratorTrainConfig(path), Catch::Contains("body_frame: true"));
  std::ofstream(path) << head << "  body_frame: true\ntrajectory:\n  epochs: 2\n"
                      << "  lr_constant_epochs: 5\n";
  CHECK_THROWS_WITH(LoadGeneratorTrainConfig(path), Catch::Contains("lr_constant_epochs"));
}

TEST_CASE("a config's training.precision parses; anything else is refused naming file and key") {
  testing::TempDir dir;
  const auto path = (dir.path() / "walker.yaml").string();
  const std::string head = "name: walker\nprotocol: bandai\ngenerator:\n  n_pre: 8\ntraining:\n";
  CHECK(Shipped("bandai").training.precision == Precision::kFp32);  // the default
  for (const auto& [text, want] : std::vector<std::pair<std::string, Precision>>{
           {"fp32", Precision::kFp32}, {"bf16", Precision::kBf16}, {"auto", Precision::kAuto}}) {
    std::ofstream(path) << head << "  precision: " << text << "\n";
    CHECK(LoadGeneratorTrainConfig(path).training.precision == want);
  }
  std::ofstream(path) << head << "  precision: fp16\n";
  CHECK_THROWS_WITH(LoadGeneratorTrainConfig(path),
                    Catch::Contains("walker.yaml") && Catch::Contains("training.precision") &&
                        Catch::Contains("expected fp32, bf16 or auto, got 'fp16'"));
}

TEST_CASE("a config's augmentation section parses, is off by default, and bad values are refused") {
  testing::TempDir dir;
  const auto path = (dir.path() / "walker.yaml").string();
  const std::string head = "name: walker\nprotocol: bandai\ngenerator:\n  n_pre: 8\n";
  CHECK_FALSE(Shipped("bandai").augmentation.enabled());  // the shipped recipe trains unvaried
  const GeneratorTrainConfig recipe = Shipped("recipes/bandai_augmented");  // the experiment's
  CHECK(recipe.augmentation.mirror == 0.5);
  CHECK(recipe.augmentation.speed == 1.3);
  const AugmentationOptions noise = Shipped("recipes/bandai_history_noise").augmentation;
  CHECK(noise.history_noise == 0.005);
  CHECK((noise.mirror == 0 && noise.scale == 1 && noise.speed == 1));
  {  // and otherwise the shipped recipe, line for line (comments, name and the section aside)
    auto lines = [](const std::string& name, bool drop_augmentation) {
      std::ifstream in(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "models", name));
      std::vector<std::string> kept;
      bool inside = false;
      for (std::string line; std::getline(in, line);) {
        if (!line.empty() && line[0] != ' ') inside = line.rfind("augmentation:", 0) == 0;
        if (line.empty() || line[0] == '#' || line.rfind("name:", 0) == 0) continue;
        if (!(inside && drop_augmentation)) kept.push_back(line);
      }
      return kept;
    };
    CHECK(lines("recipes/bandai_augmented", true) == lines("bandai", false));
    CHECK(lines("recipes/bandai_history_noise", true) == lines("bandai", false));
  }
  std::ofstream(path) << head
                      << "augmentation:\n  mirror: 0.5\n  scale: 1.1\n  speed: 1.25\n"
                         "  history_noise: 0.01\n";
  const AugmentationOptions a = LoadGeneratorTrainConfig(path).augmentation;
  CHECK(a.enabled());
  CHECK(a.mirror == 0.5);
  CHECK(a.scale == 1.1);
  CHECK(a.speed == 1.25);
  CHECK(a.history_noise == 0.01);
  std::ofstream(path) << head << "augmentation:\n  speed: 1.5\n";
  const AugmentationOptions only_speed = LoadGeneratorTrainConfig(path).augmentation;
  CHECK(only_speed.enabled());
  CHECK(only_speed.mirror == 0);  // the others stay off
  CHECK(only_speed.scale == 1);
  for (const auto& [line, message] : std::vector<std::pair<std::string, std::string>>{
           {"mirror: 1.5", "augmentation.mirror must be a share in 0..1"},
           {"mirror: .nan", "augmentation.mirror"},
           {"scale: 0.9", "augmentation.scale must be in 1..2"},
           {"speed: 0.5", "augmentation.speed must be in 1..4"},
           {"history_noise: -0.01", "augmentation.history_noise must be in 0..1 metres"}}) {
    std::ofstream(path) << head << "augmentation:\n  " << line << "\n";
    INFO(line);
    CHECK_THROWS_WITH(LoadGeneratorTrainConfig(path),
                      Catch::Contains("walker.yaml") && Catch::Contains(message));
  }
}
