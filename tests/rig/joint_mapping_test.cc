// Mapping rigs of each shipped convention onto the shipped models' skeletons by joint roles.
#include "rig/joint_mapping.h"

#include <catch2/catch.hpp>
#include <fstream>
#include <map>
#include <random>

#include "config/config_paths.h"
#include "config/rig_config.h"
#include "config/skeleton_config.h"
#include "core/error.h"
#include "test_support.h"

using namespace motionfork;

namespace {

std::shared_ptr<const Skeleton> ModelSkeleton(const std::string& name) {
  return LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", name)).skeleton;
}

const std::vector<RigConvention>& Shipped() {
  static const std::vector<RigConvention> c = LoadRigConventions(MOTIONFORK_CONFIG_DIR);
  return c;
}
const RigConvention& Convention(const std::string& name) {
  for (const RigConvention& c : Shipped())
    if (c.name == name) return c;
  throw std::runtime_error("no shipped convention " + name);
}

// A rig of `convention`: its first-choice joint for every role it names (as a flat tree under
// the pelvis; mapping reads names only), `prefix` before each name, and `extras` (fingers, twist
// bones) after them.
Skeleton MakeRig(const RigConvention& convention, const std::string& prefix,
                 const std::vector<std::string>& extras, std::vector<std::string>* roles) {
  std::vector<std::string> names;
  for (const std::string& role : BodyRoles()) {
    const auto it = convention.roles.find(role);
    if (it == convention.roles.end() || it->second[0].joints.size() != 1) continue;
    names.push_back(prefix + it->second[0].joints[0]);
    roles->push_back(role);
  }
  for (const std::string& e : extras) names.push_back(prefix + e), roles->push_back("");
  std::vector<int> parents(names.size(), 0);
  parents[0] = -1;
  return Skeleton::FromParents(convention.name + "_rig", names, parents);
}

// Positions per role for T frames (random, fixed seed), and a motion of `rig` holding them.
std::map<std::string, std::vector<float>> RolePositions(int T, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::map<std::string, std::vector<float>> out;
  for (const std::string& role : BodyRoles()) {
    auto& v = out[role];
    for (int i = 0; i < T * 3; ++i) v.push_back(u(rng));
  }
  return out;
}

Motion RigMotion(const Skeleton& rig, const std::vector<std::string>& roles,
                 const std::map<std::string, std::vector<float>>& by_role, int T) {
  const int J = rig.num_joints();
  std::vector<float> pos(static_cast<size_t>(T) * J * 3, 0.5f);
  for (int j = 0; j < J; ++j) {
    if (roles[j].empty()) continue;
    const auto& v = by_role.at(roles[j]);
    for (int t = 0; t < T; ++t)
      for (int c = 0; c < 3; ++c) pos[(static_cast<size_t>(t) * J + j) * 3 + c] = v[t * 3 + c];
  }
  return Motion(std::make_shared<const Skeleton>(rig), 60.0, std::move(pos));
}

}  // namespace

TEST_CASE("joint names compare without case, namespace prefixes and separators") {
  CHECK(NormalizeJointName("mixamorig:LeftUpLeg") == "leftupleg");
  CHECK(NormalizeJointName("Character1:Left_Up-Leg") == "leftupleg");
  CHECK(NormalizeJointName("spine_01") == "spine01");
  CHECK(NormalizeJointName("L Hip") == "lhip");
}

TEST_CASE("every shipped convention's rig is recognised and maps onto bandai's 17 joints exactly") {
  const auto model = ModelSkeleton("bandai");
  const int T = 4;
  const auto by_role = RolePositions(T, 7);
  const std::map<std::string, std::pair<std::string, std::vector<std::string>>> rigs = {
      {"mixamo",
       {"mixamorig:",
        {"Spine", "LeftHandThumb1", "LeftHandIndex1", "RightHandIndex1", "LeftToe_End",
         "RightToe_End"}}},
      {"cmu", {"", {"LHipJoint", "RHipJoint", "LowerBack", "Neck", "LThumb", "RThumb"}}},
      {"unreal", {"", {"spine_01", "upperarm_twist_01_l", "thigh_twist_01_r", "index_01_l"}}},
      {"unreal5", {"", {"spine_01", "spine_02", "spine_04", "neck_02", "upperarm_twist_01_l"}}},
      {"smpl", {"", {"spine1", "left_hand", "right_hand"}}},
      {"bandai", {"Character1:", {"Hand_L_end"}}},
  };
  for (const auto& [name, rig_spec] : rigs) {
    SECTION(name) {
      std::vector<std::string> roles;
      const Skeleton rig = MakeRig(Convention(name), rig_spec.first, rig_spec.second, &roles);
      const JointMapping m = MapJoints(rig, *model, Shipped());
      CHECK(m.source_rig == name);
      CHECK(m.target_rig == "bandai");
      CHECK(m.ignored.size() >= rig_spec.second.size());
      const Motion mapped = ApplyJointMapping(RigMotion(rig, roles, by_role, T), m, model);
      const auto model_roles = RolesOfSkeleton(*model, Shipped()).roles;
      for (int j = 0; j < model->num_joints(); ++j) {
        const auto& want = by_role.at(model_roles[j]);
        for (int t = 0; t < T; ++t)
          for (int c = 0; c < 3; ++c)
            CHECK(mapped.positions()[(static_cast<size_t>(t) * model->num_joints() + j) * 3 + c] ==
                  Approx(want[t * 3 + c]).margin(1e-6));
      }
    }
  }
}

TEST_CASE(
    "Human3.6M's 32 joints map onto the bandai model, HumanEva's 15 with spine and neck made") {
  const auto model = ModelSkeleton("bandai");
  const auto h36m32 =
      LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", "h36m")).source;
  const JointMapping h = MapJoints(*h36m32, *model, Shipped());
  CHECK(h.source_rig == "h36m");
  const int hips = model->Index("Hips"), spine = model->Index("Spine"), neck = model->Index("Neck");
  CHECK(h.described[static_cast<size_t>(spine)] == "Spine");
  CHECK(h.described[static_cast<size_t>(model->Index("Foot_L"))] == "LFoot");

  const auto humaneva = ModelSkeleton("humaneva");
  const JointMapping e = MapJoints(*humaneva, *model, Shipped());
  CHECK(e.source_rig == "humaneva");
  CHECK(e.described[static_cast<size_t>(hips)] == "Pelvis");
  // spine between pelvis and chest (Thorax); neck between chest and head.
  const auto& s = e.sources[static_cast<size_t>(spine)];
  REQUIRE(s.size() == 2);
  CHECK(s[0].second == Approx(0.5));
  CHECK(e.described[static_cast<size_t>(spine)] == "0.5 Pelvis + 0.5 Thorax");
  CHECK(e.described[static_cast<size_t>(neck)] == "0.5 Thorax + 0.5 Head");
  CHECK(e.ignored.empty());
}

TEST_CASE("a rig without a pelvis joint gets one between its hips; the mask follows") {
  const auto model = ModelSkeleton("bandai");
  std::vector<std::string> roles;
  Skeleton full = MakeRig(Convention("mixamo"), "", {}, &roles);
  // Drop the pelvis: the hips' parent is the first remaining joint.
  std::vector<std::string> names;
  for (int j = 0; j < full.num_joints(); ++j)
    if (full.joint_name(j) != "Hips") names.push_back(full.joint_name(j));
  std::vector<int> parents(names.size(), 0);
  parents[0] = -1;
  const Skeleton rig = Skeleton::FromParents("no_pelvis", names, parents);
  const JointMapping m = MapJoints(rig, *model, Shipped());
  const int hips = model->Index("Hips");
  CHECK(m.described[static_cast<size_t>(hips)] == "0.5 LeftUpLeg + 0.5 RightUpLeg");
  std::vector<uint8_t> missing(static_cast<size_t>(rig.num_joints()) * 3, 0);
  missing[static_cast<size_t>(*rig.Find("LeftUpLeg")) * 3 + 1] = 1;
  const std::vector<uint8_t> out = ApplyJointMapping(missing, m);
  CHECK(out[static_cast<size_t>(hips) * 3 + 1] == 1);
  CHECK(out[static_cast<size_t>(hips) * 3 + 0] == 0);
  CHECK(out[static_cast<size_t>(model->Index("UpperLeg_L")) * 3 + 1] == 1);
}

TEST_CASE("an unknown rig is refused naming the closest convention's missing roles") {
  const auto model = ModelSkeleton("bandai");
  const Skeleton rig = Skeleton::FromParents(
      "odd",
      {"Hips", "LeftUpLeg", "RightUpLeg", "knee_a", "knee_b", "Spine1", "Spine2", "Neck", "Head",
       "LeftArm", "LeftForeArm", "LeftHand", "RightArm", "RightForeArm", "RightHand", "LeftFoot",
       "RightFoot"},
      std::vector<int>{-1, 0, 0, 1, 2, 0, 5, 6, 7, 6, 9, 10, 6, 12, 13, 3, 4});
  CHECK_THROWS_WITH(MapJoints(rig, *model, Shipped()),
                    Catch::Contains("read as the mixamo rig, it lacks") &&
                        Catch::Contains("left_knee ('LeftLeg')") &&
                        Catch::Contains("--joint-map FILE"));
}

TEST_CASE("a joint map file maps any rig, blends included; bad maps name the line") {
  const auto model = ModelSkeleton("bandai");
  testing::TempDir dir;
  const std::string path = dir.file("my_rig.yaml");
  {
    std::ofstream f(path);
    f << "name: my_rig\njoints:\n  pelvis: {blend: [hl, hr], weights: [0.25, 0.75]}\n"
         "  spine: sp\n  chest: ch\n  neck: nk\n  head: hd\n"
         "  left_shoulder: sl\n  left_elbow: el\n  left_wrist: wl\n"
         "  right_shoulder: sr\n  right_elbow: er\n  right_wrist: wr\n"
         "  left_hip: hl\n  left_knee: kl\n  left_ankle: al\n"
         "  right_hip: hr\n  right_knee: kr\n  right_ankle: ar\n";
  }
  const RigConvention map = LoadRigConvention(path);
  const std::vector<std::string> names = {"hl", "hr", "sp", "ch", "nk", "hd", "sl", "el",    "wl",
                                          "sr", "er", "wr", "kl", "al", "kr", "ar", "finger"};
  std::vector<int> parents(names.size(), 0);
  parents[0] = -1;
  const Skeleton rig = Skeleton::FromParents("mine", names, parents);
  CHECK_THROWS_WITH(MapJoints(rig, *model, Shipped()), Catch::Contains("do not map"));
  const JointMapping m = MapJoints(rig, *model, Shipped(), &map);
  CHECK(m.source_rig == "my_rig");
  CHECK(m.described[static_cast<size_t>(model->Index("Hips"))] == "0.25 hl + 0.75 hr");
  CHECK(m.ignored == std::vector<std::string>{"finger"});

  const std::string bad = dir.file("bad.yaml");
  {
    std::ofstream f(bad);
    f << "name: bad\njoints:\n  pelvis: Hips\n  left_knees: Knee\n";
  }
  CHECK_THROWS_WITH(LoadRigConvention(bad), Catch::Contains("bad.yaml") &&
                                                Catch::Contains("line 4") &&
                                                Catch::Contains("unknown role 'left_knees'") &&
                                                Catch::Contains("left_knee"));
  {
    std::ofstream f(bad);
    f << "name: bad\njoints:\n  pelvis: {blend: [a, b], weights: [0.5]}\n";
  }
  CHECK_THROWS_WITH(LoadRigConvention(bad), Catch::Contains("expected 2 weights"));
}
