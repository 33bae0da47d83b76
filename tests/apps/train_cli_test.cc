// motionfork train end to end, as users run it, on a data folder made here: three synthetic walks
// written as BVH by `motionfork synth`, a split file, a tiny model config. Checks the bundle
// (weights, config, the training config and split it records), the log, resuming, and that
// `predict` takes the result.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/file_util.h"
#include "run_motionfork.h"
#include "test_support.h"

using Catch::Contains;
using motionfork::ReadFileBytes;
using motionfork::testing::Motionfork;
using motionfork::testing::Run;

namespace {

namespace fs = std::filesystem;

// A generator small enough to train an epoch in seconds: no prior, no angle loss.
const char* kTinyConfig = R"(name: tiny-cli
protocol: bandai
generator:
  n_pre: 4
  hidden: 16
  blocks: 1
  nz: 4
  batch_norm: true
  partition: default
losses:
  past_reconstruction: 100
  limb_length: 500
  diversity: [5, 10]
  diversity_scale: [15, 50]
  best_of_many: 2
  multimodal: 1
multimodal:
  last_pose_threshold: 0.05
  future_min_distance: 0.1
  max_per_window: 4
training:
  samples_per_part: [2, 2]
  batch_histories: 2
  epochs: 2
  windows_per_epoch: 4
  lr_constant_epochs: 1
  learning_rate: 0.001
  grad_clip: 100
  window_stride: 10
  seed: 0
  threads: 1
)";

}  // namespace

TEST_CASE(
    "train on a synthetic data folder: bundle with its training config and split, log, resume, "
    "predict") {
  motionfork::testing::TempDir dir;
  const std::string data = dir.file("data"), out = dir.file("run"), config = dir.file("tiny.yaml");
  fs::create_directories(data);
  int heading = 0;
  for (const char* clip : {"walk_a", "walk_b", "walk_c"}) {
    const Run r = Motionfork("synth walk --frames 160 --heading " + std::to_string(heading += 40) +
                             " -o " + data + "/" + clip + ".bvh");
    REQUIRE(r.status == 0);
  }
  std::ofstream(data + "/split.tsv") << "train\twalk_a.bvh\ntrain\twalk_b.bvh\ntest\twalk_c.bvh\n";
  std::ofstream(dir.file("split_ab.tsv"))
      << "train\twalk_a.bvh\ntest\twalk_b.bvh\ntest\twalk_c.bvh\n";
  std::ofstream(config) << "# the test's config\n" << kTinyConfig;

  Run r = Motionfork("-q train --config " + config + " --data " + data + " --split " +
                     dir.file("split_ab.tsv") + " --out " + out + " --stop-after 1");
  INFO(r.output);
  REQUIRE(r.status == 0);
  for (const char* f : {"model.yaml", "generator.pt", "log.csv", "training.yaml"}) {
    CHECK(fs::is_regular_file(fs::path(out) / f));
  }
  // The recipe and the clips it saw travel with the weights.
  const std::string split_ab = dir.file("split_ab.tsv");
  const std::string recorded = ReadFileBytes(out + "/training.yaml");
  CHECK_THAT(recorded, Contains("# --- the config file as read ---\n# the test's config\n" +
                                std::string(kTinyConfig)));
  CHECK_THAT(recorded, Contains("# split: " + split_ab + "\n"));
  const std::string model = ReadFileBytes(out + "/model.yaml");
  CHECK_THAT(model, Contains("split: " + split_ab));
  CHECK_THAT(model, Contains("training_config: training.yaml"));
  CHECK_THAT(model, Contains("config: tiny-cli"));

  const std::string same =
      "train --config " + config + " --data " + data + " --split " + split_ab + " --out " + out;
  auto log_rows = [&] {
    int rows = 0;
    std::ifstream log(out + "/log.csv");
    for (std::string line; std::getline(log, line);) rows += !line.empty();
    return rows;
  };
  // Running the same command again resumes at epoch 2 and finishes.
  r = Motionfork(same);
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Contains("resuming from"));
  CHECK_THAT(r.output, Contains("epoch 2/2"));
  CHECK(log_rows() == 3);  // header + two epochs

  // Another config, or the same one without its split, is refused before anything is trained,
  // also when the other config is the recorded one's tail (the file without its first line).
  std::string other = kTinyConfig;
  other.replace(other.find("learning_rate: 0.001"), 20, "learning_rate: 0.002");
  std::ofstream(dir.file("other.yaml")) << other;
  std::ofstream(dir.file("tail.yaml")) << kTinyConfig;
  for (const std::string& cfg : {dir.file("other.yaml"), dir.file("tail.yaml")}) {
    r = Motionfork("-q train --config " + cfg + " --data " + data + " --split " + split_ab +
                   " --out " + out + " --epochs 3");
    CHECK(r.status == 2);
    CHECK_THAT(r.output,
               Contains(out + "/training.yaml") && Contains("another config than now (" + cfg));
  }
  r = Motionfork("-q train --config " + config + " --data " + data + " --out " + out +
                 " --epochs 3");
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("another split than now (the protocol's own)"));
  CHECK(log_rows() == 3);
  CHECK_THAT(ReadFileBytes(out + "/training.yaml"), Contains("learning_rate: 0.001"));
  // --epochs may change: one more epoch, recorded.
  r = Motionfork("-q " + same + " --epochs 3");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(log_rows() == 4);
  CHECK_THAT(ReadFileBytes(out + "/training.yaml"), Contains("--epochs 3 on the command line"));
  // --precision too (auto: bf16 products where the CPU has them), recorded; a bad value refused.
  r = Motionfork("-q " + same + " --epochs 4 --precision auto");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(log_rows() == 5);
  CHECK_THAT(ReadFileBytes(out + "/training.yaml"),
             Contains("--precision auto on the command line replaced training.precision"));
  r = Motionfork("-q " + same + " --epochs 5 --precision fp16");
  CHECK(r.status != 0);
  CHECK_THAT(r.output, Contains("--precision") && Contains("fp16"));
  CHECK(log_rows() == 5);

  // The bundle predicts; without --split the protocol's own split is recorded.
  r = Motionfork("predict --model " + out + " --history " + data + "/walk_c.bvh -k 3 --seed 1 -o " +
                 dir.file("futures.npy"));
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK(fs::is_regular_file(dir.file("futures.npy")));
  r = Motionfork("-q train --config " + config + " --data " + data + " --out " + dir.file("run2") +
                 " --epochs 1");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(ReadFileBytes(dir.file("run2") + "/model.yaml"),
             Contains("split: the protocol's own"));
  CHECK_THAT(ReadFileBytes(dir.file("run2") + "/training.yaml"),
             Contains("# split: the protocol's own\n"));
  CHECK_THAT(ReadFileBytes(dir.file("run2") + "/training.yaml"),
             Contains("--epochs 1 on the command line"));
}

TEST_CASE(
    "train: a trajectory section added to a finished body-frame run trains the trajectory, once, "
    "and predict moves the root") {
  motionfork::testing::TempDir dir;
  const std::string data = dir.file("data"), out = dir.file("run");
  fs::create_directories(data);
  int heading = 0;
  for (const char* clip : {"walk_a", "walk_b", "walk_c"}) {
    const Run r = Motionfork("synth walk --frames 160 --heading " + std::to_string(heading += 40) +
                             " -o " + data + "/" + clip + ".bvh");
    REQUIRE(r.status == 0);
  }
  std::ofstream(data + "/split.tsv") << "train\twalk_a.bvh\ntrain\twalk_b.bvh\ntest\twalk_c.bvh\n";
  std::string body = kTinyConfig;
  body.replace(body.find("  partition: default\n"), 21,
               "  partition: default\n  body_frame: true\n");
  std::ofstream(dir.file("body.yaml")) << body;
  const std::string train = "-q train --data " + data + " --out " + out + " --config ";
  Run r = Motionfork(train + dir.file("body.yaml"));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_FALSE(fs::exists(out + "/trajectory"));

  // The same config with a trajectory section: the generator's epochs are done, the trajectory
  // trains into OUT/trajectory/ and the recorded config is the new one.
  std::ofstream(dir.file("body_trajectory.yaml"))
      << body
      << "trajectory:\n  hidden: 16\n  layers: 1\n  epochs: 2\n  lr_constant_epochs: 1\n"
         "  batch: 8\n  window_stride: 10\n  validation_every: 0\n";
  r = Motionfork(train + dir.file("body_trajectory.yaml"));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Contains("trajectory:") && Contains("kept epoch 2"));
  CHECK(fs::is_regular_file(out + "/trajectory/trajectory.yaml"));
  CHECK_THAT(ReadFileBytes(out + "/training.yaml"), Contains("trajectory:\n  hidden: 16"));
  r = Motionfork(train + dir.file("body_trajectory.yaml"));
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Contains("already trained"));

  // The generator's own settings still may not change.
  std::string other = body;
  other.replace(other.find("learning_rate: 0.001"), 20, "learning_rate: 0.002");
  std::ofstream(dir.file("other.yaml")) << other;
  r = Motionfork(train + dir.file("other.yaml"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("another config than now"));

  r = Motionfork("predict --model " + out + " --history " + data + "/walk_c.bvh -k 3 --seed 1 -o " +
                 dir.file("futures"));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(ReadFileBytes(dir.file("futures.json")), Contains("\"root_moves\": true"));
}
