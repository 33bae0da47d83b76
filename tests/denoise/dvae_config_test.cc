// Motion-DVAE configs and bundle manifests.
#include <catch2/catch.hpp>
#include <fstream>

#include "bundle/dvae_bundle.h"
#include "config/config_paths.h"
#include "core/error.h"
#include "test_support.h"

using namespace motionfork;
using Catch::Contains;

TEST_CASE("the shipped dvae_bandai config parses with the paper's latent size") {
  const DvaeTrainConfig c =
      LoadDvaeTrainConfig(std::string(MOTIONFORK_CONFIG_DIR) + "/models/dvae_bandai.yaml");
  CHECK(c.protocol == "bandai");
  CHECK(c.model.window == 30);
  CHECK(c.model.latent == 48);
  CHECK(c.model.groups == 16);
  CHECK(c.finetune.noise.size() >= 3);
  CHECK(c.refiner.model.enabled());
  CHECK(c.refiner.model.reach() >= 15);
  const DvaeTrainConfig r =
      LoadDvaeTrainConfig(std::string(MOTIONFORK_CONFIG_DIR) + "/models/dvae_reference.yaml");
  CHECK(r.model.hidden == 1024);
  CHECK(r.training.epochs == 200);
  CHECK(r.training.batch_size == 64);
}

TEST_CASE(
    "dvae configs: missing keys take defaults, unknown keys and bad values are errors naming the "
    "file") {
  const DvaeTrainConfig c = ParseDvaeTrainConfig("protocol: bandai\n", "cfg.yaml");
  CHECK(c.model.hidden == 1024);
  CHECK(c.denoise.mode == DenoiseMode::kRegression);
  CHECK_THROWS_WITH(ParseDvaeTrainConfig("protocol: bandai\nmodel:\n  hiden: 3\n", "cfg.yaml"),
                    Contains("cfg.yaml") && Contains("hiden"));
  CHECK_THROWS_WITH(ParseDvaeTrainConfig(
                        "protocol: bandai\nmodel:\n  mlp_hidden: 30\n  groups: 16\n", "cfg.yaml"),
                    Contains("multiple of groups"));
  CHECK_THROWS_WITH(
      ParseDvaeTrainConfig("protocol: bandai\nfinetune:\n  noise: [gaussian:x]\n", "cfg.yaml"),
      Contains("cfg.yaml") && Contains("not a number"));
  CHECK_THROWS_WITH(ParseDvaeTrainConfig("protocol: bandai\ndenoise:\n  mode: magic\n", "cfg.yaml"),
                    Contains("regression"));
  CHECK_THROWS_WITH(
      ParseDvaeTrainConfig("protocol: bandai\nnoise_prior:\n  scale: 0\n", "cfg.yaml"),
      Contains("scale > 0"));
  CHECK_THROWS_WITH(ParseDvaeTrainConfig("protocol: bandai\nrefiner:\n  chanels: 3\n", "cfg.yaml"),
                    Contains("cfg.yaml") && Contains("refiner.chanels"));
  CHECK_THROWS_WITH(
      ParseDvaeTrainConfig("protocol: bandai\nrefiner:\n  dilations: [1, 0]\n", "cfg.yaml"),
      Contains("cfg.yaml") && Contains("dilations"));
  CHECK_THROWS_WITH(
      ParseDvaeTrainConfig("protocol: bandai\nrefiner:\n  clean_share: 1\n", "cfg.yaml"),
      Contains("clean_share"));
  CHECK_THROWS_WITH(
      ParseDvaeTrainConfig("protocol: bandai\nrefiner:\n  accel_weight: -1\n", "cfg.yaml"),
      Contains("accel_weight >= 0"));
  CHECK(ParseDvaeTrainConfig("protocol: bandai\nrefiner:\n  accel_weight: 0.5\n", "cfg.yaml")
            .refiner.accel_weight == 0.5);
  // A config asking for refiner mode: the bundles trained before the refiner use regression mode.
  const DvaeTrainConfig r =
      ParseDvaeTrainConfig("protocol: bandai\ndenoise:\n  mode: refiner\n", "cfg.yaml");
  CHECK(r.denoise.mode == DenoiseMode::kRefiner);
}

TEST_CASE("dvae manifests round-trip exactly") {
  DvaeManifest m;
  m.protocol = "bandai";
  m.fps = 30;
  m.model.hidden = 64;
  m.skeleton = testing::MakeHumanoid()->ToSpec();
  const size_t F = 3 * m.skeleton.joint_names.size();
  for (size_t i = 0; i < F; ++i) {
    m.mean.push_back(0.1 * i + 1.0 / 3.0);
    m.std.push_back(0.2 + i / 7.0);
  }
  m.noise_prior.dof = 3.5;
  m.finetuned = true;
  m.finetune_noise = {"gaussian:0.05", "outliers:0.1,0.3"};
  m.denoise.mode = DenoiseMode::kOptimisation;
  m.denoise.fuse = false;
  m.info = {{"config", "x"}};
  testing::TempDir dir;
  const std::string path = dir.file("dvae.yaml");
  { std::ofstream(path) << FormatDvaeManifest(m); }
  const DvaeManifest b = LoadDvaeManifest(path);
  CHECK(FormatDvaeManifest(b) == FormatDvaeManifest(m));
  CHECK(b.mean == m.mean);
  CHECK(b.finetune_noise == m.finetune_noise);
  CHECK(b.denoise.mode == DenoiseMode::kOptimisation);
  CHECK_FALSE(b.denoise.fuse);
  CHECK_FALSE(b.refiner.enabled());
  CHECK(FormatDvaeManifest(b).find("refiner") == std::string::npos);  // older bundles: the same
  m.refiner = {24, 40, 8, {1, 3}, 5};
  m.denoise.mode = DenoiseMode::kRefiner;
  { std::ofstream(path) << FormatDvaeManifest(m); }
  const DvaeManifest c = LoadDvaeManifest(path);
  CHECK(FormatDvaeManifest(c) == FormatDvaeManifest(m));
  CHECK(c.refiner.dilations == std::vector<int>{1, 3});
  CHECK(c.refiner.linear_reach == 5);
  m.refiner = {};
  { std::ofstream(path) << FormatDvaeManifest(m); }
  CHECK_THROWS_WITH(LoadDvaeManifest(path), Contains("has no refiner"));
  { std::ofstream(path) << "format: motionfork-dvae-0\n"; }
  CHECK_THROWS_WITH(LoadDvaeManifest(path), Contains("dvae.yaml") && Contains("motionfork-dvae-1"));
}
