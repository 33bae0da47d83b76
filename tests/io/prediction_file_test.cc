#include "io/prediction_file.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "io/npy.h"
#include "test_support.h"

namespace motionfork {
namespace {

using testing::MakeHumanoid;
using testing::TempDir;

Prediction MakePrediction(int k) {
  Prediction p;
  p.model = "models/x";
  p.protocol = "bandai";
  p.history = "walk.bvh";
  p.start_frame = 4;
  p.k = k;
  p.t_his = 3;
  p.t_pred = 5;
  p.seed = 12345678901234ULL;
  p.fps = 30;
  p.skeleton = MakeHumanoid();
  p.fixed_parts = {"legs"};
  p.root_moves = true;
  p.positions.resize(static_cast<size_t>(k) * p.frames() * p.joints() * 3);
  for (size_t i = 0; i < p.positions.size(); ++i)
    p.positions[i] = 0.001f * static_cast<float>(i % 977) - 0.3f;
  for (int s = 0; s < k; ++s) {
    SampleValidity v;
    v.valid = s % 2 == 0;
    v.violating_frames = s % 2;
    if (s != 1) v.prior_nll = -40.5 + s;
    p.samples.push_back(v);
  }
  p.history_validity = SampleValidity{true, 0, -42.25};
  return p;
}

TEST_CASE("prediction files round-trip every field", "[io][prediction]") {
  TempDir dir;
  const Prediction p = MakePrediction(3);
  const std::string base = WritePrediction(dir.file("out.npy"), p);
  CHECK(base == dir.file("out"));
  for (const std::string& path : {dir.file("out.json"), dir.file("out.npy"), dir.file("out")}) {
    const Prediction q = ReadPrediction(path);
    CHECK(q.model == p.model);
    CHECK(q.protocol == p.protocol);
    CHECK(q.history == p.history);
    CHECK(q.start_frame == 4);
    CHECK(q.seed == p.seed);
    CHECK(q.k == 3);
    CHECK(q.t_his == 3);
    CHECK(q.t_pred == 5);
    CHECK(q.fps == 30);
    CHECK(q.positions == p.positions);
    CHECK(q.skeleton->joint_names() == p.skeleton->joint_names());
    CHECK(q.skeleton->parents() == p.skeleton->parents());
    CHECK(q.skeleton->left_right_pairs() == p.skeleton->left_right_pairs());
    REQUIRE(q.skeleton->partitions().size() == 1);
    const auto& parts = q.skeleton->GetPartition().parts;
    REQUIRE(parts.size() == 2);
    CHECK(parts[0].name == "legs");
    CHECK(parts[0].joints == p.skeleton->GetPartition().parts[0].joints);
    CHECK(q.fixed_parts == std::vector<std::string>{"legs"});
    CHECK(q.root_moves);
    REQUIRE(q.samples.size() == 3);
    CHECK(q.samples[0].valid);
    CHECK_FALSE(q.samples[1].valid);
    CHECK(q.samples[1].violating_frames == 1);
    CHECK_FALSE(q.samples[1].prior_nll.has_value());
    CHECK(*q.samples[2].prior_nll == -38.5);
    REQUIRE(q.history_validity);
    CHECK(*q.history_validity->prior_nll == -42.25);
    // Sample accessor: the second sample starts T*J*3 floats in.
    CHECK(q.sample(1)[0] == p.positions[static_cast<size_t>(q.frames()) * q.joints() * 3]);
  }
}

TEST_CASE("prediction files: bad input names the file and what is wrong", "[io][prediction]") {
  TempDir dir;
  CHECK_THROWS_WITH(ReadPrediction(dir.file("missing.json")),
                    Catch::Contains("missing.json") && Catch::Contains("not found"));
  const Prediction p = MakePrediction(2);
  WritePrediction(dir.file("a"), p);

  SECTION("array of another shape") {
    NpyArray arr;
    arr.shape = {3, p.frames(), p.joints(), 3};
    arr.data.assign(static_cast<size_t>(3) * p.frames() * p.joints() * 3, 0.0f);
    WriteNpy(dir.file("a.npy"), arr);
    CHECK_THROWS_WITH(ReadPrediction(dir.file("a.json")),
                      Catch::Contains("a.npy") && Catch::Contains("expected shape [2, 8, 17, 3]") &&
                          Catch::Contains("found [3, 8, 17, 3]"));
  }
  SECTION("broken JSON") {
    std::ofstream(dir.file("a.json")) << "{\"k\": 2,";
    CHECK_THROWS_AS(ReadPrediction(dir.file("a.json")), FormatError);
  }
  SECTION("missing key") {
    std::ofstream(dir.file("a.json")) << "{\"k\": 2, \"fps\": 30, \"t_his\": 3}";
    CHECK_THROWS_WITH(ReadPrediction(dir.file("a.json")), Catch::Contains("missing key 't_pred'"));
  }
  SECTION("wrong type") {
    std::ofstream(dir.file("a.json")) << "{\"k\": \"two\"}";
    CHECK_THROWS_WITH(ReadPrediction(dir.file("a.json")), Catch::Contains("key 'k'"));
  }
  SECTION("writer refuses inconsistent sizes") {
    Prediction bad = p;
    bad.positions.pop_back();
    CHECK_THROWS_AS(WritePrediction(dir.file("b"), bad), std::invalid_argument);
    CHECK_FALSE(std::filesystem::exists(dir.file("b.json")));
  }
}

}  // namespace
}  // namespace motionfork
