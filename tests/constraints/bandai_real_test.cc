// The constraint sets on real motion capture (../shared/data/bandai, read from its archives).
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>

#include "config/protocol_config.h"
#include "constraints/fit.h"
#include "dataset/dataset.h"
#include "fixtures.h"
#include "test_support.h"

using namespace motionfork;
using namespace motionfork::testing;

namespace {

// Loaded once for every test case here (the first load parses the archives, ~10 s).
const Dataset* Bandai() {
  static std::unique_ptr<Dataset> ds;
  static bool tried = false;
  if (tried) return ds.get();
  tried = true;
  const std::string data = SharedDataDir("data/bandai");
  if (data.empty()) return nullptr;
  DatasetLoadOptions opts;
  opts.cache_dir = TestCacheDir();
  const ProtocolOptions p =
      LoadProtocolConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "protocols", "bandai"));
  ds = std::make_unique<Dataset>(LoadDataset(p, ShippedSkeleton(p.skeleton), data, opts));
  return ds.get();
}

struct Rates {
  long long frames = 0, invalid = 0;
  std::vector<long long> violations, below;
};

// clips: indices; rename: the skeleton the positions are read as (same joint count and order).
Rates Measure(const ConstraintSet& set, const Dataset& ds, const std::vector<int>& clips,
              const std::shared_ptr<const Skeleton>& as = nullptr) {
  Rates r;
  r.violations.assign(set.num_constraints(), 0);
  r.below.assign(set.num_constraints(), 0);
  for (int i : clips) {
    const Motion& m = ds.clips[i].motion;
    const CheckResult res = as ? Check(set, Motion(as, m.fps(), m.positions())) : Check(set, m);
    r.frames += res.num_frames;
    for (int t = 0; t < res.num_frames; ++t) {
      bool bad = false;
      for (int c = 0; c < res.num_constraints; ++c) {
        r.violations[c] += IsViolation(res.at(t, c));
        r.below[c] += res.at(t, c) == AngleStatus::kBelow;
        bad |= res.at(t, c) != AngleStatus::kInside;
      }
      r.invalid += bad;
    }
  }
  return r;
}

void Report(const std::string& title, const ConstraintSet& set, const Rates& r) {
  std::string text = title + ": " + std::to_string(r.frames) + " frames, " +
                     std::to_string(100.0 * r.invalid / r.frames) + "% outside some range\n";
  for (int c = 0; c < set.num_constraints(); ++c) {
    char line[160];
    std::snprintf(line, sizeof(line), "  %-24s [%6.1f, %6.1f]  %.4f%% (below %.4f%%)\n",
                  set.constraint(c).name.c_str(), set.constraint(c).lower_deg,
                  set.constraint(c).upper_deg, 100.0 * r.violations[c] / r.frames,
                  100.0 * r.below[c] / r.frames);
    text += line;
  }
  WARN(text);
}

// The Bandai 17 joints renamed for another skeleton's constraints (same order as H36M's), so
// the seed's definitions and ranges can be tried on real motion. Bandai's Neck sits where
// H36M's thorax does (at the shoulders; Bandai's Chest is lower), so it plays the thorax.
std::shared_ptr<const Skeleton> Renamed(const Skeleton& bandai,
                                        const std::vector<std::string>& names) {
  std::vector<std::pair<int, int>> pairs = bandai.left_right_pairs();
  return std::make_shared<const Skeleton>(
      Skeleton::FromParents("bandai_as_other", names, bandai.parents(), pairs));
}

}  // namespace

TEST_CASE("bandai real data: the fitted ranges hold on the held-out test split (per constraint)") {
  const Dataset* ds = Bandai();
  if (!ds) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  const ConstraintSet set = ShippedSet("bandai", *ds->skeleton.skeleton);
  const Rates test = Measure(set, *ds, ds->ClipIndices(Split::kTest));
  REQUIRE(test.frames > 50000);
  Report("fitted bandai ranges on the Bandai TEST split (elderly style, unseen in fitting)", set,
         test);
  for (int c = 0; c < set.num_constraints(); ++c) {
    INFO(set.constraint(c).name);
    CHECK(test.violations[c] < 0.002 * test.frames);
  }
  CHECK(test.invalid < 0.01 * test.frames);
  const Rates train = Measure(set, *ds, ds->ClipIndices(Split::kTrain));
  Report("fitted bandai ranges on the Bandai train split", set, train);
  CHECK(train.invalid < 0.02 * train.frames);
}

TEST_CASE("bandai real data: the committed bandai.yaml is what the fit command produces") {
  const Dataset* ds = Bandai();
  if (!ds) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  const ConstraintSetSpec committed = ShippedConstraints("bandai");
  const ConstraintSet set = ConstraintSet::Build(committed, *ds->skeleton.skeleton);
  RangeFitter fitter(set);  // the command's defaults: 0 / 100, 5 degrees, rounded to 0.1
  for (int i : ds->ClipIndices(Split::kTrain)) fitter.Add(ds->clips[i].motion);
  const ConstraintSetSpec refit = WithFittedRanges(committed, fitter.Fit());
  for (size_t i = 0; i < committed.constraints.size(); ++i) {
    INFO(committed.constraints[i].name);
    CHECK(refit.constraints[i].lower_deg ==
          Approx(committed.constraints[i].lower_deg).margin(1e-6));
    CHECK(refit.constraints[i].upper_deg ==
          Approx(committed.constraints[i].upper_deg).margin(1e-6));
  }
}

TEST_CASE("bandai real data: the seed's definitions and Table 1 ranges hold on real motion") {
  const Dataset* ds = Bandai();
  if (!ds) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  const Skeleton& b = *ds->skeleton.skeleton;
  std::vector<int> all = ds->ClipIndices(Split::kTrain);
  for (int i : ds->ClipIndices(Split::kTest)) all.push_back(i);

  // H36M: every Table 1 angle except the head plane (Bandai has no nose joint).
  {
    const auto as_h36m = Renamed(
        b, {"Hips", "RHip", "RKnee", "RFoot", "LHip", "LKnee", "LFoot", "Spine", "Chest", "Thorax",
            "Neck", "LShoulder", "LElbow", "LWrist", "RShoulder", "RElbow", "RWrist"});
    ConstraintSetSpec spec = ShippedConstraints("h36m");
    spec.constraints.erase(
        std::remove_if(spec.constraints.begin(), spec.constraints.end(),
                       [](const ConstraintSpec& c) { return c.name == "HeadPlane2TorsoPlane"; }),
        spec.constraints.end());
    const ConstraintSet set = ConstraintSet::Build(spec, *as_h36m);
    const Rates r = Measure(set, *ds, all, as_h36m);
    Report("h36m definitions + Table 1 ranges on all Bandai frames (Neck as thorax, Head as nose)",
           set, r);
    for (int c = 0; c < set.num_constraints(); ++c) {
      INFO(set.constraint(c).name);
      CHECK(r.violations[c] < 0.001 * r.frames);
    }
  }
  // HumanEva: its motion is walking, jogging, boxing and gestures; compare with Bandai's walking.
  {
    const auto as_humaneva = Renamed(
        b, {"Pelvis", "RHip", "RKnee", "RAnkle", "LHip", "LKnee", "LAnkle", "Spine", "Chest",
            "Thorax", "Head", "LShoulder", "LElbow", "LWrist", "RShoulder", "RElbow", "RWrist"});
    const ConstraintSet set = ShippedSet("humaneva", *as_humaneva);
    std::vector<int> walks;
    for (int i : all) {
      if (ds->clips[i].action == "walk") walks.push_back(i);
    }
    REQUIRE(walks.size() > 100);
    const Rates r = Measure(set, *ds, walks, as_humaneva);
    Report("humaneva definitions + Table 1 ranges on Bandai walking (Neck as thorax)", set, r);
    // Bandai's walking includes exaggerated styles (giant, childish, ...) whose swing-phase knee
    // flexion passes HumanEva's 76 degrees (Leg2ThighPlane above 166); a wrongly oriented
    // definition would instead put most frames outside.
    for (int c = 0; c < set.num_constraints(); ++c) {
      INFO(set.constraint(c).name);
      CHECK(r.violations[c] < 0.02 * r.frames);
      CHECK(r.below[c] < 0.001 * r.frames);
    }
  }
}

TEST_CASE("bandai real data: impossible versions of real poses fire the fitted constraints") {
  const Dataset* ds = Bandai();
  if (!ds) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  const Skeleton& s = *ds->skeleton.skeleton;
  const ConstraintSet set = ShippedSet("bandai", s);
  int tried = 0;
  for (int i : ds->ClipIndices(Split::kTest)) {
    if (i % 10 != 0) continue;
    const Motion& m = ds->clips[i].motion;
    const Pose real(m.frame(m.num_frames() / 2), m.frame(m.num_frames() / 2) + 51);
    if (!CheckPose(set, real).Fired(set).empty()) continue;
    ++tried;
    INFO(ds->clips[i].name);
    const BodyAxes ax = Axes(s, real, "UpperLeg_L", "UpperLeg_R", "Hips", "Chest");
    Pose knee = real;
    {
      // The shin put 40 degrees in front of the thigh's line, in the plane of its bend.
      const Eigen::Vector3f hip = At(s, knee, "UpperLeg_L"), kn = At(s, knee, "LowerLeg_L");
      const Eigen::Vector3f thigh = (kn - hip).normalized();
      const Eigen::Vector3f normal = thigh.cross(hip - At(s, knee, "Hips")).normalized();
      const float shin = (At(s, knee, "Foot_L") - kn).norm();
      const float a = 50 * static_cast<float>(M_PI) / 180;
      Eigen::Map<Eigen::Vector3f>(knee.data() + 3 * s.Index("Foot_L")) =
          kn + shin * (std::cos(a) * normal + std::sin(a) * thigh);
    }
    CHECK(CheckPose(set, knee).Fires(set, "Leg2ThighPlane_L"));
    Pose head = real;  // folded backwards (Bandai's head has no face point to show a turn)
    Rotate(s, &head, {"Head"}, At(s, head, "Neck"), ax.left, 180);
    CHECK(CheckPose(set, head).Fires(set, "Head2Neck"));
    Pose arm = real;
    Rotate(s, &arm, {"UpperArm_R", "LowerArm_R", "Hand_R"}, At(s, arm, "Chest"), ax.up, -160);
    const PoseCheck a = CheckPose(set, arm);
    CHECK((a.Fires(set, "Shoulder2Shoulder") || a.Fires(set, "Shoulder2Hip_R")));
    Pose front = real;
    Rotate(s, &front, {"LowerLeg_L", "Foot_L"}, At(s, front, "UpperLeg_L"), ax.left, -100);
    Rotate(s, &front, {"LowerLeg_R", "Foot_R"}, At(s, front, "UpperLeg_R"), ax.left, 100);
    CHECK(CheckPose(set, front).Fires(set, "Thigh2TorsoPlane_R"));
    Pose side = real;
    Rotate(s, &side, {"LowerLeg_L", "Foot_L"}, At(s, side, "UpperLeg_L"), ax.forward, 100);
    Rotate(s, &side, {"LowerLeg_R", "Foot_R"}, At(s, side, "UpperLeg_R"), ax.forward, -100);
    const PoseCheck sd = CheckPose(set, side);
    CHECK(sd.Fires(set, "ThighPlane2TorsoPlane_L"));
    CHECK(sd.Fires(set, "ThighPlane2TorsoPlane_R"));
  }
  CHECK(tried >= 20);
}
