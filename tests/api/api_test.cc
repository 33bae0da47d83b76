// The public API (include/motionfork/motionfork.h) on a tiny bundle written in code, checked
// against the libraries it wraps (Forecaster, the angle checker's own summary).
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "bundle/generator_bundle.h"
#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "config/skeleton_config.h"
#include "constraints/checker.h"
#include "constraints/constraint_set.h"
#include "core/demo_motion.h"
#include "generator/inference/forecaster.h"
#include "io/motion_file.h"
#include "motionfork/motionfork.h"
#include "test_support.h"
#include "tiny_bundle.h"

using namespace motionfork;
using Catch::Contains;

namespace {

// One bundle per process (CTest runs each case in its own).
const std::string& Bundle() {
  static testing::TempDir dir;
  static const std::string path = [] {
    const std::string p = dir.file("bundle");
    testing::WriteTinyBundle(p, MOTIONFORK_CONFIG_DIR);
    return p;
  }();
  return path;
}

LoadOptions Options(const std::string& config_dir, const std::string& constraints, int threads) {
  LoadOptions o;
  o.config_dir = config_dir;
  o.constraints = constraints;
  o.threads = threads;
  return o;
}

Model LoadTiny(LoadOptions options = {}) {
  if (options.config_dir.empty()) options.config_dir = MOTIONFORK_CONFIG_DIR;
  return Model::Load(Bundle(), options);
}

const std::vector<float>& History() {
  static const std::vector<float> h = testing::TinyBundleHistory(12).positions();
  return h;
}

// Sets an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_.empty()) {
      unsetenv(name_);
    } else {
      setenv(name_, old_.c_str(), 1);
    }
  }

 private:
  const char* name_;
  std::string old_;
};

}  // namespace

TEST_CASE("Model::Load gives the bundle's skeleton, parts, sizes and constraint set") {
  const Model model = LoadTiny();
  const auto humanoid = testing::MakeHumanoid();  // the Bandai protocol joints, in their order
  CHECK(model.joint_names() == humanoid->joint_names());
  CHECK(model.parents() == humanoid->parents());
  CHECK(model.left_right_pairs().size() == 6);
  REQUIRE(model.parts().size() == 2);
  CHECK(model.parts()[0].name == "legs");
  CHECK(model.parts()[0].joints == std::vector<std::string>{"UpperLeg_R", "LowerLeg_R", "Foot_R",
                                                            "UpperLeg_L", "LowerLeg_L", "Foot_L"});
  CHECK(model.parts()[1].name == "upper");
  CHECK(model.parts()[1].joints.size() == 10);  // every joint but the root and the legs
  CHECK(model.history_frames() == 5);
  CHECK(model.future_frames() == 10);
  CHECK(model.fps() == 30.0);
  CHECK(model.protocol() == "bandai");
  CHECK(model.constraint_set() == "bandai");  // the shipped set named like the protocol
  CHECK(std::filesystem::equivalent(
      model.constraint_file(), std::string(MOTIONFORK_CONFIG_DIR) + "/constraints/bandai.yaml"));
  CHECK(model.config_dir() == MOTIONFORK_CONFIG_DIR);
}

TEST_CASE("Model::Predict gives k futures of future_frames frames, as the Forecaster does") {
  const Model model = LoadTiny();
  const Futures f = model.Predict(History(), {6, 11, {}});
  CHECK(f.k == 6);
  CHECK(f.frames == 10);
  CHECK(f.joints == 17);
  CHECK(f.fps == 30.0);
  REQUIRE(f.positions.size() == 6u * 10 * 17 * 3);
  for (float v : f.positions) REQUIRE(std::isfinite(v));
  CHECK(f.sample(2) == f.positions.data() + 2 * 10 * 17 * 3);

  // The history's last 5 frames, through the Forecaster directly (built fp32; the API's default
  // is auto).
  Forecaster forecaster = LoadForecaster(Bundle());
  forecaster.SetPrecision(Precision::kAuto);
  const Motion history(forecaster.skeleton(), 30.0, History());
  ForecastRequest request;
  request.k = 6;
  request.seed = 11;
  CHECK(forecaster.Predict(history, 12 - 5, request).futures == f.positions);
  // Only those frames matter.
  const std::vector<float> last5(History().end() - 5 * 17 * 3, History().end());
  CHECK(model.Predict(last5, {6, 11, {}}).positions == f.positions);
}

TEST_CASE("LoadOptions::precision: fp32, bf16 where the CPU has AVX512-BF16, auto") {
  CHECK(ParsePrecision("fp32") == Precision::kFp32);
  CHECK(ParsePrecision("bf16") == Precision::kBf16);
  CHECK(ParsePrecision("auto") == Precision::kAuto);
  CHECK_THROWS_WITH(ParsePrecision("fp16"), Contains("expected fp32, bf16 or auto, got 'fp16'"));
  CHECK(ResolvePrecision(Precision::kAuto) ==
        (Bf16ProductsAvailable() ? Precision::kBf16 : Precision::kFp32));
  LoadOptions o;
  o.precision = "fp16";
  CHECK_THROWS_WITH(LoadTiny(o), Contains("expected fp32, bf16 or auto"));
  CHECK(LoadOptions().precision == "auto");  // the default
  o.precision = "fp32";
  const Futures fp32 = LoadTiny(o).Predict(History(), {6, 11, {}});
  o.precision = "auto";
  const Futures any = LoadTiny(o).Predict(History(), {6, 11, {}});
  CHECK(LoadTiny().Predict(History(), {6, 11, {}}).positions == any.positions);
  o.precision = "bf16";
  if (!Bf16ProductsAvailable()) {
    CHECK_THROWS_WITH(LoadTiny(o), Contains("AVX512-BF16"));
    CHECK(any.positions == fp32.positions);  // auto: fp32 here
    return;
  }
  // bf16 products: other futures (the hidden layers' inputs rounded), close to fp32's.
  const Futures bf16 = LoadTiny(o).Predict(History(), {6, 11, {}});
  CHECK(any.positions == bf16.positions);  // auto: bf16 here
  CHECK(bf16.positions != fp32.positions);
  double worst = 0;
  for (size_t i = 0; i < bf16.positions.size(); ++i)
    worst = std::max(worst, double(std::abs(bf16.positions[i] - fp32.positions[i])));
  CHECK(worst < 0.01);
  // The Forecaster switches back and forth.
  Forecaster forecaster = LoadForecaster(Bundle());
  const Motion history(forecaster.skeleton(), 30.0, History());
  ForecastRequest request;
  request.k = 6;
  request.seed = 11;
  forecaster.SetPrecision(Precision::kBf16);
  CHECK(forecaster.precision() == Precision::kBf16);
  CHECK(forecaster.Predict(history, 7, request).futures == bf16.positions);
  forecaster.SetPrecision(Precision::kFp32);
  CHECK(forecaster.Predict(history, 7, request).futures == fp32.positions);
}

TEST_CASE("Model::Predict: the same seed gives the same futures, another seed others") {
  const Model model = LoadTiny();
  const Futures a = model.Predict(History(), {4, 3, {}});
  CHECK(model.Predict(History(), {4, 3, {}}).positions == a.positions);
  CHECK(LoadTiny().Predict(History(), {4, 3, {}}).positions == a.positions);  // a second load
  CHECK(model.Predict(History(), {4, 4, {}}).positions != a.positions);
  // The futures differ from each other.
  CHECK(!std::equal(a.sample(0), a.sample(1), a.sample(1)));
}

TEST_CASE("Model::Predict: a fixed first part is identical in every future, the rest varies") {
  const Model model = LoadTiny();
  const Futures f = model.Predict(History(), {5, 0, {"legs"}});
  const std::vector<std::string>& names = model.joint_names();
  float legs = 0, upper = 0;
  for (int k = 1; k < f.k; ++k) {
    for (int t = 0; t < f.frames; ++t) {
      for (int j = 1; j < f.joints; ++j) {
        const std::vector<std::string>& leg_joints = model.parts()[0].joints;
        const bool in_legs =
            std::find(leg_joints.begin(), leg_joints.end(), names[j]) != leg_joints.end();
        for (int a = 0; a < 3; ++a) {
          const size_t i = (static_cast<size_t>(t) * f.joints + j) * 3 + a;
          const float d = std::abs(f.sample(k)[i] - f.sample(0)[i]);
          (in_legs ? legs : upper) = std::max(in_legs ? legs : upper, d);
        }
      }
    }
  }
  CHECK(legs == 0.0f);
  CHECK(upper > 1e-4f);
  // Without fixing, the legs vary too.
  const Futures free = model.Predict(History(), {5, 0, {}});
  CHECK(!std::equal(free.sample(0), free.sample(0) + 17 * 3 * 10, free.sample(1)));
}

TEST_CASE("Model::Check agrees with the checker's own summary, sample by sample") {
  const Model model = LoadTiny();
  const Futures f = model.Predict(History(), {8, 1, {}});
  const std::vector<SampleCheck> checks = model.Check(f);
  REQUIRE(checks.size() == 8);
  const ConstraintSet set = ConstraintSet::Build(
      LoadConstraintConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "constraints", "bandai")),
      *testing::MakeHumanoid());
  int invalid = 0;
  for (int k = 0; k < f.k; ++k) {
    INFO("sample " << k);
    const Motion sample(testing::MakeHumanoid(), 30.0,
                        std::vector<float>(f.sample(k), f.sample(k) + 10 * 17 * 3));
    const CheckSummary s = Summarize(set, Check(set, sample));
    const SampleCheck& c = checks[k];
    CHECK(c.valid == (s.valid_frames == s.frames));
    CHECK(c.violating_frames.size() == static_cast<size_t>(s.violating_frames));
    CHECK(c.undefined_frames.size() == static_cast<size_t>(s.degenerate_frames));
    std::vector<std::string> violated;
    for (int i = 0; i < set.num_constraints(); ++i) {
      if (s.constraints[i].violations() > 0) violated.push_back(set.constraint(i).name);
    }
    CHECK(c.violated_constraints == violated);
    for (int t : c.violating_frames) CHECK((t >= 0 && t < 10));
    invalid += !c.valid;
    // CheckMotion on the same frames says the same.
    const SampleCheck again = model.CheckMotion(sample.positions());
    CHECK(again.violating_frames == c.violating_frames);
    CHECK(again.violated_constraints == c.violated_constraints);
  }
  CHECK(invalid > 0);  // untrained weights: some futures break the ranges
}

TEST_CASE("Model::CheckMotion: standing is valid, a head bent back and a zero-length bone not") {
  const Model model = LoadTiny();
  // Standing, arms hanging, knees slightly bent (metres; x = the body's left, y up, z forward).
  // Bandai's Chest joint sits low, between the shoulder blades' level and the waist.
  const std::map<std::string, std::array<float, 3>> standing = {
      {"Hips", {0, 1.00f, 0}},
      {"UpperLeg_R", {-0.1f, 0.966f, 0}},
      {"LowerLeg_R", {-0.1f, 0.55f, 0.03f}},
      {"Foot_R", {-0.1f, 0.10f, -0.02f}},
      {"UpperLeg_L", {0.1f, 0.966f, 0}},
      {"LowerLeg_L", {0.1f, 0.55f, 0.03f}},
      {"Foot_L", {0.1f, 0.10f, -0.02f}},
      {"Spine", {0, 1.10f, -0.01f}},
      {"Chest", {0, 1.25f, 0}},
      {"Neck", {0, 1.50f, 0.01f}},
      {"Head", {0, 1.65f, 0.02f}},
      {"UpperArm_L", {0.17f, 1.47f, 0}},
      {"LowerArm_L", {0.19f, 1.19f, -0.02f}},
      {"Hand_L", {0.20f, 0.94f, 0.04f}},
      {"UpperArm_R", {-0.17f, 1.47f, 0}},
      {"LowerArm_R", {-0.19f, 1.19f, -0.02f}},
      {"Hand_R", {-0.20f, 0.94f, 0.04f}}};
  const std::vector<std::string>& names = model.joint_names();
  std::vector<float> frames;
  for (int t = 0; t < 4; ++t) {
    for (const std::string& n : names) {
      for (float v : standing.at(n)) frames.push_back(v);
    }
  }
  auto at = [&](int t, const std::string& joint) {
    const auto j = std::find(names.begin(), names.end(), joint) - names.begin();
    return &frames[(static_cast<size_t>(t) * names.size() + j) * 3];
  };
  const SampleCheck still = model.CheckMotion(frames);
  CHECK(still.valid);
  CHECK(still.violating_frames.empty());
  CHECK(still.undefined_frames.empty());
  CHECK(still.violated_constraints.empty());
  // Frame 1: the head tipped 90 degrees back (behind the neck); frame 3: the left foot on the
  // left knee.
  at(1, "Head")[1] = at(1, "Neck")[1];
  at(1, "Head")[2] = at(1, "Neck")[2] - 0.13f;
  std::copy(at(3, "LowerLeg_L"), at(3, "LowerLeg_L") + 3, at(3, "Foot_L"));
  const SampleCheck moved = model.CheckMotion(frames);
  CHECK_FALSE(moved.valid);
  CHECK(moved.violating_frames == std::vector<int>{1});
  CHECK(moved.violated_constraints == std::vector<std::string>{"Head2Neck"});
  CHECK(moved.undefined_frames == std::vector<int>{3});
  // An undefined angle alone makes a motion invalid: frames 2 and 3.
  const SampleCheck undefined_only =
      model.CheckMotion(std::vector<float>(frames.begin() + 2 * 17 * 3, frames.end()));
  CHECK(undefined_only.violating_frames.empty());
  CHECK(undefined_only.undefined_frames == std::vector<int>{1});
  CHECK_FALSE(undefined_only.valid);
}

TEST_CASE("Model::ReadMotion maps a file onto the model's joints and frame rate") {
  const Model model = LoadTiny();
  testing::TempDir dir;
  const Motion at60 = testing::TinyBundleHistory(20, 60.0);
  WriteMotionFile(dir.file("walk60.csv"), at60);
  const std::vector<float> read = model.ReadMotion(dir.file("walk60.csv"));
  REQUIRE(read.size() == 10u * 17 * 3);  // 20 frames at 60 Hz -> 10 at 30 Hz
  for (int t = 0; t < 10; ++t) {
    for (int i = 0; i < 17 * 3; ++i) {
      REQUIRE(read[t * 51 + i] == Approx(at60.frame(2 * t)[i]).margin(1e-5));
    }
  }
  CHECK(model.Predict(read, {2, 0, {}}).k == 2);
  CHECK_THROWS_WITH(model.ReadMotion(dir.file("missing.csv")), Contains("missing.csv"));
}

TEST_CASE("Model: errors say what was expected and what was found") {
  testing::TempDir dir;
  CHECK_THROWS_AS(Model::Load(dir.file("nowhere")), std::runtime_error);
  CHECK_THROWS_WITH(Model::Load(dir.file("nowhere")), Contains("nowhere") && Contains("not found"));
  std::filesystem::create_directories(dir.path() / "empty");
  CHECK_THROWS_WITH(Model::Load(dir.file("empty")), Contains("model.yaml"));

  const Model model = LoadTiny();
  const std::vector<float>& h = History();
  CHECK_THROWS_AS(model.Predict(std::vector<float>(h.begin(), h.end() - 1)), std::invalid_argument);
  CHECK_THROWS_WITH(
      model.Predict(std::vector<float>(h.begin(), h.end() - 1)),
      Contains("expected [T, 17, 3]") && Contains("multiple of 51") && Contains("got 611"));
  CHECK_THROWS_WITH(model.Predict(std::vector<float>(h.begin(), h.begin() + 4 * 51)),
                    Contains("at least 5 frames") && Contains("got 4"));
  CHECK_THROWS_WITH(model.Predict({}), Contains("got 0 values"));
  std::vector<float> nan = h;
  nan[(9 * 17 + 2) * 3 + 1] = NAN;
  CHECK_THROWS_WITH(model.Predict(nan), Contains("frame 9") && Contains("LowerLeg_R"));
  CHECK_THROWS_WITH(model.Predict(h, {3, 0, {"tail"}}),
                    Contains("no body part 'tail'") && Contains("legs, upper"));
  CHECK_THROWS_WITH(model.Predict(h, {0, 0, {}}),
                    Contains("1..10000 futures") && Contains("got 0"));

  Futures f = model.Predict(h, {2, 0, {}});
  f.positions.pop_back();
  CHECK_THROWS_WITH(model.Check(f), Contains("expected futures [k, frames, 17, 3]"));

  const Model unchecked = LoadTiny(Options("", "none", 0));
  CHECK(unchecked.constraint_set().empty());
  CHECK_THROWS_AS(unchecked.Check(model.Predict(h, {2, 0, {}})), std::logic_error);
  CHECK_THROWS_WITH(unchecked.CheckMotion(h), Contains("no constraint set"));
  CHECK_THROWS_WITH(LoadTiny(Options("", "elbows", 0)),
                    Contains("'elbows'") && Contains("bandai, h36m, humaneva"));
  CHECK_THROWS_WITH(LoadTiny(Options(dir.file("nowhere"), "", 0)),
                    Contains("LoadOptions::config_dir") && Contains("not a folder"));
  CHECK_THROWS_WITH(LoadTiny(Options("", "", -1)), Contains("threads") && Contains("got -1"));
}

TEST_CASE("Model::Load: constraints from the option, the bundle, the configs folder") {
  testing::TempDir dir;
  // A copy of the shipped bandai set under another name.
  std::ifstream in(std::string(MOTIONFORK_CONFIG_DIR) + "/constraints/bandai.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t name = text.find("\nname: bandai\n");
  REQUIRE(name != std::string::npos);
  text.replace(name, 14, "\nname: copied\n");
  std::filesystem::create_directories(dir.path() / "configs" / "constraints");
  std::ofstream(dir.path() / "configs" / "constraints" / "bandai.yaml") << text;

  SECTION("$MOTIONFORK_CONFIG_DIR, unless the option names a folder") {
    const std::string configs = (dir.path() / "configs").string();
    ScopedEnv env("MOTIONFORK_CONFIG_DIR", configs);
    const Model model = Model::Load(Bundle());
    CHECK(model.config_dir() == configs);
    CHECK(model.constraint_set() == "copied");  // the protocol's set in that folder
    CHECK(LoadTiny().constraint_set() == "bandai");
  }
  SECTION("$MOTIONFORK_CONFIG_DIR must be a folder") {
    ScopedEnv env("MOTIONFORK_CONFIG_DIR", dir.file("missing"));
    CHECK_THROWS_WITH(Model::Load(Bundle()),
                      Contains("$MOTIONFORK_CONFIG_DIR") && Contains("missing"));
  }
  SECTION("the bundle's own constraints.yaml before the protocol's shipped set") {
    const std::string bundle = dir.file("bundle");
    testing::WriteTinyBundle(bundle, MOTIONFORK_CONFIG_DIR);
    std::ofstream(dir.path() / "bundle" / "constraints.yaml") << text;
    LoadOptions options;
    options.config_dir = MOTIONFORK_CONFIG_DIR;
    const Model model = Model::Load(bundle, options);
    CHECK(model.constraint_set() == "copied");
    CHECK(model.constraint_file() == (dir.path() / "bundle" / "constraints.yaml").string());
    options.constraints = "bandai";  // the option wins
    CHECK(Model::Load(bundle, options).constraint_set() == "bandai");
  }
}

TEST_CASE("the shipped model: repaired futures pass Check, fixed legs stay identical") {
  LoadOptions options;
  options.config_dir = MOTIONFORK_CONFIG_DIR;
  const Model model = Model::Load(std::string(MOTIONFORK_SOURCE_DIR) + "/models/bandai", options);
  const auto skeleton =
      LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", "bandai")).skeleton;
  const std::vector<float> history = MakeDemoWalk(skeleton).positions();  // Bandai protocol order
  PredictOptions repaired{20, 3, {"legs"}};
  const Futures a = model.Predict(history, repaired);
  // Repair keeps every future inside the angle ranges; the prior judges the poses on top (a
  // repaired pose can be an unusual one: its NLL above the bound).
  int prior_ok = 0;
  for (const SampleCheck& s : model.Check(a)) {
    INFO("prior NLL " << s.prior_nll << ", bound " << model.prior_bound());
    CHECK(s.violating_frames.empty());
    CHECK(s.undefined_frames.empty());
    CHECK(s.valid == s.prior_ok);
    CHECK(s.failed ==
          (s.prior_ok ? std::vector<std::string>{} : std::vector<std::string>{"prior_nll"}));
    CHECK(s.prior_ok == (s.prior_nll <= model.prior_bound()));
    prior_ok += s.prior_ok;
  }
  CHECK(prior_ok >= 15);
  PredictOptions raw = repaired;
  raw.repair = false;
  const Futures b = model.Predict(history, raw);
  CHECK(a.positions != b.positions);  // the raw output breaks some range (the pelvis) somewhere
  // Legs identical across the futures in both.
  for (const Futures* f : {&a, &b}) {
    const size_t per = static_cast<size_t>(f->frames) * f->joints * 3;
    const int hip = 4;  // UpperLeg_L in the Bandai protocol order
    for (int k = 1; k < f->k; ++k) {
      for (int t = 0; t < f->frames; ++t) {
        for (int c = 0; c < 3; ++c) {
          const size_t i = (static_cast<size_t>(t) * f->joints + hip) * 3 + c;
          CHECK(f->positions[k * per + i] == f->positions[i]);
        }
      }
    }
  }
}
