// PoseValidator: angle ranges and the pose prior of a model bundle, judged on the demo walk (a
// plausible motion the project makes itself) and on the same walk with a knee bent backwards.
#include "validity/pose_validator.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "config/config_paths.h"
#include "config/skeleton_config.h"
#include "core/demo_motion.h"
#include "core/error.h"
#include "test_support.h"

namespace motionfork {
namespace {

namespace fs = std::filesystem;

const std::string kConstraints = std::string(MOTIONFORK_CONFIG_DIR) + "/constraints/bandai.yaml";
const std::string kPrior = std::string(MOTIONFORK_SOURCE_DIR) + "/models/prior-bandai";

std::shared_ptr<const Skeleton> BandaiSkeleton() {
  return LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", "bandai"))
      .skeleton;
}

// The walk with the left knee pushed 15 cm behind the hip-ankle line from frame `from` on.
Motion WithBackwardKnee(const Motion& walk, int from) {
  std::vector<float> p = walk.positions();
  const Skeleton& s = walk.skeleton();
  const int J = s.num_joints(), knee = s.Index("LowerLeg_L"), hip = s.Index("UpperLeg_L"),
            ankle = s.Index("Foot_L");
  for (int t = from; t < walk.num_frames(); ++t) {
    float* f = &p[static_cast<size_t>(t) * J * 3];
    for (int c = 0; c < 3; ++c) f[3 * knee + c] = 0.5f * (f[3 * hip + c] + f[3 * ankle + c]);
    f[3 * knee + 2] -= 0.15f;  // -z: behind the body of a walker heading +z
  }
  return Motion(walk.skeleton_ptr(), walk.fps(), std::move(p));
}

TEST_CASE("the demo walk is plausible, a backward knee violates and costs prior likelihood") {
  const auto skeleton = BandaiSkeleton();
  DemoWalkOptions options;
  options.frames = 45;
  const Motion walk = MakeDemoWalk(skeleton, options);
  const PoseValidator v(skeleton, 30, kConstraints, kPrior);
  REQUIRE(v.has_constraints());
  REQUIRE(v.has_prior());
  CHECK_THAT(v.described(), Catch::Contains("angles: ") && Catch::Contains("prior: "));

  const std::vector<double> flags = v.ViolationFlags(walk.positions().data(), walk.num_frames());
  REQUIRE(flags.size() == 45u);
  for (double f : flags) CHECK(f == 0.0);
  const SampleValidity good = v.Score(walk.positions().data(), walk.num_frames());
  CHECK(good.valid);
  CHECK(good.violating_frames == 0);
  REQUIRE(good.prior_nll.has_value());
  const std::vector<double> nll = v.PriorNll(walk.positions().data(), walk.num_frames());
  double mean = 0;
  for (double x : nll) mean += x / nll.size();
  CHECK(*good.prior_nll == Approx(mean).epsilon(1e-12));

  const Motion bad = WithBackwardKnee(walk, 30);
  const std::vector<double> bad_flags = v.ViolationFlags(bad.positions().data(), bad.num_frames());
  for (int t = 0; t < 45; ++t) CHECK(bad_flags[t] == (t >= 30 ? 1.0 : 0.0));
  const SampleValidity worse = v.Score(bad.positions().data(), bad.num_frames());
  CHECK_FALSE(worse.valid);
  CHECK(worse.violating_frames == 15);
  const std::vector<double> bad_nll = v.PriorNll(bad.positions().data(), bad.num_frames());
  for (int t = 30; t < 45; ++t) CHECK(bad_nll[t] > nll[t] + 5.0);  // nats per pose
}

TEST_CASE("a bundle carries its judges: AttachToBundle then FromBundle gives the same figures") {
  const auto skeleton = BandaiSkeleton();
  const Motion walk = MakeDemoWalk(skeleton);
  testing::TempDir dir;
  const std::string bundle = (dir.path() / "bundle").string();

  const PoseValidator none = PoseValidator::FromBundle(bundle, skeleton, 30);
  CHECK_FALSE(none.has_constraints());
  CHECK_FALSE(none.has_prior());
  CHECK(none.described().empty());
  const SampleValidity nothing = none.Score(walk.positions().data(), walk.num_frames());
  CHECK(nothing.valid);
  CHECK_FALSE(nothing.prior_nll.has_value());

  AttachToBundle(bundle, kConstraints, "");
  const PoseValidator angles_only = PoseValidator::FromBundle(bundle, skeleton, 30);
  CHECK(angles_only.has_constraints());
  CHECK_FALSE(angles_only.has_prior());

  AttachToBundle(bundle, "", kPrior);
  const PoseValidator both = PoseValidator::FromBundle(bundle, skeleton, 30);
  const PoseValidator direct(skeleton, 30, kConstraints, kPrior);
  REQUIRE(both.has_prior());
  const Motion bad = WithBackwardKnee(walk, 10);
  const SampleValidity a = both.Score(bad.positions().data(), bad.num_frames());
  const SampleValidity b = direct.Score(bad.positions().data(), bad.num_frames());
  CHECK(a.violating_frames == b.violating_frames);
  CHECK(a.violating_frames == bad.num_frames() - 10);
  CHECK(*a.prior_nll == *b.prior_nll);  // the copied prior is the same prior, bit for bit
}

TEST_CASE("broken judges are refused with the file named") {
  const auto skeleton = BandaiSkeleton();
  testing::TempDir dir;
  // A prior folder without its files.
  fs::create_directories(dir.path() / "empty_prior");
  CHECK_THROWS_WITH(PoseValidator(skeleton, 30, "", (dir.path() / "empty_prior").string()),
                    Catch::Contains("prior.yaml"));
  CHECK_THROWS_WITH(
      AttachToBundle((dir.path() / "b").string(), "", (dir.path() / "empty_prior").string()),
      Catch::Contains("prior.yaml"));
  CHECK_FALSE(fs::exists(dir.path() / "b" / "prior"));
  // A constraint set naming joints this skeleton does not have (H36M's on Bandai).
  CHECK_THROWS(PoseValidator(skeleton, 30,
                             std::string(MOTIONFORK_CONFIG_DIR) + "/constraints/h36m.yaml", ""));
  // A constraint file that is not YAML.
  const std::string junk = (dir.path() / "junk.yaml").string();
  std::ofstream(junk) << "constraints: [unclosed\n";
  CHECK_THROWS_WITH(PoseValidator(skeleton, 30, junk, ""), Catch::Contains("junk.yaml"));
  // The Bandai prior on the H36M skeleton (other joints): refused.
  const auto h36m =
      LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", "h36m")).skeleton;
  CHECK_THROWS(PoseValidator(h36m, 50, "", kPrior));
}

}  // namespace
}  // namespace motionfork
