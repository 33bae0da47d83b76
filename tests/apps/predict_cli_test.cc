// motionfork predict / export / synth end to end on a tiny bundle written in code (random weights,
// Bandai skeleton) that carries the shipped Bandai constraint set and pose prior.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include "api/tiny_bundle.h"
#include "io/csv.h"
#include "io/motion_file.h"
#include "io/prediction_file.h"
#include "run_motionfork.h"
#include "test_support.h"
#include "validity/pose_validator.h"

using namespace motionfork;
using Catch::Contains;
using testing::Motionfork;
using testing::Run;

namespace {

namespace fs = std::filesystem;

struct Fixture {
  testing::TempDir dir;
  std::string bundle = dir.file("bundle"), history = dir.file("history.csv");
  Fixture() {
    testing::WriteTinyBundle(bundle, MOTIONFORK_CONFIG_DIR);
    AttachToBundle(bundle, std::string(MOTIONFORK_CONFIG_DIR) + "/constraints/bandai.yaml",
                   std::string(MOTIONFORK_SOURCE_DIR) + "/models/prior-bandai");
    WriteCsvMotion(history, testing::TinyBundleHistory(12));
  }
  Run Predict(const std::string& out, const std::string& extra = "") const {
    return Motionfork("predict --model " + bundle + " --history " + history + " -k 6 -o " +
                      dir.file(out) + " " + extra);
  }
};

// Largest |a - b| over the joints of one part, across every pair of samples' futures.
double PartSpread(const Prediction& p, const std::vector<int>& joints) {
  double worst = 0;
  for (int k = 1; k < p.k; ++k) {
    for (int t = p.t_his; t < p.frames(); ++t) {
      for (int j : joints) {
        for (int c = 0; c < 3; ++c) {
          const size_t i = (static_cast<size_t>(t) * p.joints() + j) * 3 + c;
          worst = std::max(worst, std::abs(double(p.sample(k)[i]) - p.sample(0)[i]));
        }
      }
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("predict writes K futures with per-sample validity, --fix shares a part, seeds") {
  Fixture f;
  Run r = f.Predict("a");
  INFO(r.output);
  REQUIRE(r.status == 0);
  // The tiny bundle's history is no human pose: the gate doubts it and no future is valid.
  CHECK_THAT(r.output, Contains("0 of 6 futures valid (angle ranges, prior NLL <= "));
  CHECK_THAT(r.output, Contains("far from what the model knows: angle ranges: "));
  CHECK_THAT(r.output, Contains("prior NLL"));
  const Prediction a = ReadPrediction(f.dir.file("a.json"));
  CHECK(a.k == 6);
  CHECK(a.t_his == 5);
  CHECK(a.t_pred == 10);
  CHECK(a.joints() == 17);
  CHECK(a.positions.size() == 6u * 15 * 17 * 3);
  REQUIRE(a.samples.size() == 6u);
  REQUIRE(a.history_validity.has_value());
  REQUIRE(a.history_check.has_value());
  CHECK_FALSE(a.history_check->doubts.empty());
  // The JSON's figures are the validator's own, recomputed here from the written positions.
  const PoseValidator v = PoseValidator::FromBundle(f.bundle, a.skeleton, a.fps);
  for (int k = 0; k < a.k; ++k) {
    const SampleValidity s =
        v.Score(a.sample(k) + static_cast<size_t>(a.t_his) * a.joints() * 3, a.t_pred);
    CHECK(a.samples[k].violating_frames == s.violating_frames);
    CHECK(a.samples[k].prior_ok == s.prior_ok);
    CHECK_FALSE(a.samples[k].history_ok);  // the gate doubted the history
    CHECK_FALSE(a.samples[k].valid);
    REQUIRE(a.samples[k].prior_nll.has_value());
    CHECK(*a.samples[k].prior_nll == Approx(*s.prior_nll).epsilon(1e-6));
  }

  // Same seed: the same futures, bit for bit; another seed: other futures.
  REQUIRE(f.Predict("again").status == 0);
  CHECK(ReadPrediction(f.dir.file("again.npy")).positions == a.positions);
  REQUIRE(f.Predict("other", "--seed 5").status == 0);
  CHECK(ReadPrediction(f.dir.file("other.json")).positions != a.positions);

  // --fix legs: leg joints identical across samples (spread exactly 0), the upper body varies.
  for (const std::string part : {"legs", "upper"}) {
    r = f.Predict("fix_" + part, "--fix " + part);
    INFO(r.output);
    REQUIRE(r.status == 0);
    const Prediction p = ReadPrediction(f.dir.file("fix_" + part + ".json"));
    CHECK(p.fixed_parts == std::vector<std::string>{part});
    const Partition& parts = p.skeleton->GetPartition();
    for (const BodyPart& bp : parts.parts) {
      if (bp.name == part) {
        CHECK(PartSpread(p, bp.joints) == 0.0);
      } else {
        CHECK(PartSpread(p, bp.joints) > 1e-4);
      }
    }
  }
}

TEST_CASE("predict refuses bad input with the file named and writes nothing") {
  Fixture f;
  // A history with a NaN: a value of frame `frame` replaced in the file's text (12 frames; the
  // history is the last 5, frames 7..11).
  auto with_nan = [&f](int frame, const std::string& name) {
    std::ifstream in(f.history);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()), line,
        out;
    std::istringstream lines(text);
    int data_row = -1;
    while (std::getline(lines, line)) {
      if (!line.empty() && line[0] != '#' && data_row++ == frame)
        line = "nan" + line.substr(line.find(','));
      out += line + "\n";
    }
    std::ofstream(f.dir.file(name)) << out;
    return f.dir.file(name);
  };
  Run r = Motionfork("predict --model " + f.bundle + " --history " + with_nan(9, "nan.csv") +
                     " -k 4 -o " + f.dir.file("nan_out"));
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("nan.csv") && Contains("1 missing values") && Contains("--impute"));
  CHECK_FALSE(fs::exists(f.dir.file("nan_out.npy")));
  // A NaN in a frame the history does not use is no obstacle.
  r = Motionfork("predict --model " + f.bundle + " --history " + with_nan(2, "early_nan.csv") +
                 " -k 4 -o " + f.dir.file("early_out"));
  CHECK(r.status == 0);
  // Too short: 3 frames for a 5-frame history.
  WriteCsvMotion(f.dir.file("short.csv"), testing::TinyBundleHistory(3));
  r = Motionfork("predict --model " + f.bundle + " --history " + f.dir.file("short.csv") +
                 " -k 4 -o " + f.dir.file("short_out"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("short.csv"));
  // A part the skeleton does not have.
  r = f.Predict("nopart", "--fix tail");
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("tail"));
  // A bundle whose prior is broken: named, not a crash.
  fs::remove(fs::path(f.bundle) / "prior" / "weights.npy");
  r = f.Predict("broken");
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("prior"));
  CHECK_FALSE(fs::exists(f.dir.file("broken.json")));
}

TEST_CASE("predict with several histories writes each file's futures as predicted alone") {
  Fixture f;
  const std::string second = f.dir.file("second.csv");
  WriteCsvMotion(second, testing::TinyBundleHistory(17));
  REQUIRE(f.Predict("alone1").status == 0);
  REQUIRE(
      Motionfork("predict --model " + f.bundle + " " + second + " -k 6 -o " + f.dir.file("alone2"))
          .status == 0);
  for (int threads : {1, 2}) {
    const std::string out = f.dir.file("many" + std::to_string(threads));
    const Run r = Motionfork("predict --model " + f.bundle + " " + f.history + " " + second +
                             " -k 6 --threads " + std::to_string(threads) + " -o " + out);
    INFO(r.output);
    REQUIRE(r.status == 0);
    // Reported in the order of the files, whatever the threads.
    CHECK(r.output.find(out + "/history.npy") < r.output.find(out + "/second.npy"));
    const Prediction one = ReadPrediction(out + "/history.json");
    const Prediction two = ReadPrediction(out + "/second.json");
    CHECK(one.history == f.history);
    CHECK(one.positions == ReadPrediction(f.dir.file("alone1.json")).positions);
    CHECK(two.positions == ReadPrediction(f.dir.file("alone2.json")).positions);
    CHECK(one.positions != two.positions);
  }
  // Two files of one name would write one output: refused before anything is written.
  fs::create_directories(f.dir.file("other"));
  WriteCsvMotion(f.dir.file("other/history.csv"), testing::TinyBundleHistory(12));
  const Run clash = Motionfork("predict --model " + f.bundle + " " + f.history + " " +
                               f.dir.file("other/history.csv") + " -o " + f.dir.file("clash"));
  CHECK(clash.status == 2);
  CHECK_THAT(clash.output, Contains("other/history.csv") && Contains("different file names"));
  CHECK_FALSE(fs::exists(f.dir.file("clash")));
  // A bad file among good ones: nothing is written, the file is named.
  const std::string short_history = f.dir.file("short.csv");
  WriteCsvMotion(short_history, testing::TinyBundleHistory(3));
  const Run bad = Motionfork("predict --model " + f.bundle + " " + f.history + " " + short_history +
                             " --threads 2 -o " + f.dir.file("bad"));
  CHECK(bad.status == 2);
  CHECK_THAT(bad.output, Contains("short.csv") && Contains("history frames"));
  CHECK_FALSE(fs::exists(f.dir.file("bad")));
}

TEST_CASE("export writes each predicted sample as BVH that reads back to the prediction") {
  Fixture f;
  REQUIRE(f.Predict("p").status == 0);
  Run r = Motionfork("export " + f.dir.file("p.json") + " -o " + f.dir.file("s.bvh") +
                     " --lengths exact");
  INFO(r.output);
  REQUIRE(r.status == 0);
  const Prediction p = ReadPrediction(f.dir.file("p.json"));
  for (int k = 0; k < p.k; ++k) {
    const std::string path = f.dir.file("s_0" + std::to_string(k) + ".bvh");
    REQUIRE(fs::exists(path));
    const Motion m = ReadMotionFile(path);
    REQUIRE(m.num_frames() == p.frames());
    REQUIRE(m.num_joints() == p.joints());
    double worst = 0;
    for (size_t i = 0; i < m.positions().size(); ++i) {
      worst = std::max(worst, std::abs(double(m.positions()[i]) - p.sample(k)[i]));
    }
    CHECK(worst < 1e-3);  // metres: within 1 mm (exact lengths keep every position)
  }
  // One sample to one file; a sample that does not exist; a path that is not .bvh.
  REQUIRE(Motionfork("export " + f.dir.file("p.npy") + " --sample 2 -o " + f.dir.file("two.bvh"))
              .status == 0);
  CHECK(fs::exists(f.dir.file("two.bvh")));
  r = Motionfork("export " + f.dir.file("p.json") + " --sample 9 -o " + f.dir.file("nine.bvh"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("0..5"));
  r = Motionfork("export " + f.dir.file("p.json") + " -o " + f.dir.file("out.txt"));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains(".bvh"));
}

TEST_CASE("synth walk writes a plausible history on the Bandai skeleton") {
  testing::TempDir dir;
  Run r = Motionfork("synth walk --frames 45 -o " + dir.file("walk.npy"));
  INFO(r.output);
  REQUIRE(r.status == 0);
  r = Motionfork("check " + dir.file("walk.npy") + " --skeleton bandai");
  INFO(r.output);
  CHECK(r.status == 0);  // every frame inside the Bandai angle ranges
  CHECK_THAT(r.output, Contains("valid frames: 45 of 45"));
  r = Motionfork("synth walk --skeleton h36m -o " + dir.file("h.npy"));
  CHECK(r.status == 2);
  CHECK_FALSE(fs::exists(dir.file("h.npy")));
}
