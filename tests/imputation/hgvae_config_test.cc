// HG-VAE configs and bundle manifests.
#include <catch2/catch.hpp>
#include <fstream>

#include "bundle/hgvae_bundle.h"
#include "core/error.h"
#include "test_support.h"

using namespace motionfork;
using Catch::Contains;

TEST_CASE("hgvae config: the shipped config parses with every key") {
  const HgvaeTrainConfig c =
      LoadHgvaeTrainConfig(std::string(MOTIONFORK_CONFIG_DIR) + "/models/hgvae_bandai.yaml");
  CHECK(c.protocol == "bandai");
  REQUIRE(c.model.levels.size() == 4);
  CHECK(c.model.levels[0].nodes == 1);
  CHECK(c.model.levels[0].features == 256);
  CHECK(c.model.levels[3].nodes == 0);
  CHECK(c.training.condition == "action");
  CHECK(c.impute.steps == 10);
  const HgvaeOptions r = ResolveHgvaeOptions(c.model, 48, 15);
  CHECK(r.levels[3].nodes == 48);
  CHECK(r.window == 15);
}

TEST_CASE("hgvae config: unknown keys and bad sizes are errors naming the key") {
  CHECK_THROWS_WITH(ParseHgvaeTrainConfig("protocol: bandai\nmodel:\n  widht: 3\n", "x.yaml"),
                    Contains("x.yaml") && Contains("widht"));
  CHECK_THROWS_WITH(
      ParseHgvaeTrainConfig("protocol: bandai\nmodel:\n  levels: [[1, 8], [4, 8]]\n", "x.yaml"),
      Contains("(bottom) level must be the full graph"));
  CHECK_THROWS_WITH(
      ParseHgvaeTrainConfig("protocol: bandai\nimpute:\n  objective: magic\n", "x.yaml"),
      Contains("posterior"));
  CHECK_THROWS_WITH(ParseHgvaeTrainConfig("protocol: bandai\nimpute:\n  start: cubic\n", "x.yaml"),
                    Contains("spline"));
  CHECK(ParseHgvaeTrainConfig("protocol: bandai\nimpute:\n  start: spline\n", "x.yaml")
            .impute.start == ImputeStart::kSpline);
  CHECK_THROWS_WITH(
      ParseHgvaeTrainConfig("protocol: bandai\ntraining:\n  condition: style\n", "x.yaml"),
      Contains("condition"));
}

TEST_CASE("hgvae config: a manifest survives a round trip exactly") {
  testing::TempDir dir;
  HgvaeManifest m;
  m.protocol = "bandai";
  m.fps = 30;
  m.model = ResolveHgvaeOptions(HgvaeOptions{}, 48, 15);
  m.skeleton = testing::MakeHumanoid()->ToSpec();
  m.classes = {"run", "walk"};
  for (int i = 0; i < 48; ++i) {
    m.mean.push_back(0.1 * i + 1.0 / 3);
    m.std.push_back(0.2 + i / 7.0);
  }
  m.score_mean = -1234.5678901234;
  m.score_std = 98.7654321;
  m.impute.objective = ImputeObjective::kPosterior;
  m.info = {{"config", "x"}};
  const std::string path = dir.file("hgvae.yaml");
  std::ofstream(path) << FormatHgvaeManifest(m);
  const HgvaeManifest r = LoadHgvaeManifest(path);
  CHECK(r.mean == m.mean);
  CHECK(r.std == m.std);
  CHECK(r.score_mean == m.score_mean);
  CHECK(r.classes == m.classes);
  CHECK(r.model.levels[3].nodes == 48);
  CHECK(r.impute.objective == ImputeObjective::kPosterior);
  CHECK(r.skeleton.joint_names == m.skeleton.joint_names);
  CHECK(FormatHgvaeManifest(r) == FormatHgvaeManifest(m));
  // The mean start is not written (bundles from before the key re-emit as they were); another is.
  CHECK(FormatHgvaeManifest(m).find("start") == std::string::npos);
  m.impute.start = ImputeStart::kLinear;
  std::ofstream(path) << FormatHgvaeManifest(m);
  CHECK(LoadHgvaeManifest(path).impute.start == ImputeStart::kLinear);
}
