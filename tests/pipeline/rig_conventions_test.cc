// Every built-in rig convention (configs/rigs/), made in code from a Bandai-skeleton walk (the
// convention's joint names, extra finger, toe and twist joints), in metres, centimetres,
// millimetres and inches, Y, Z and X up, at 24, 60 and 120 Hz: it maps onto the shipped model,
// its unit and up axis are told right, the way back gives the file's own values, and the shipped
// model forecasts from it what it forecasts from the Bandai walk (the joints a rig lacks made as
// the mapping makes them).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <map>

#include "bundle/generator_bundle.h"
#include "config/config_paths.h"
#include "config/rig_config.h"
#include "config/skeleton_config.h"
#include "core/demo_motion.h"
#include "core/resample.h"
#include "generator/inference/forecaster.h"
#include "pipeline/motion_input.h"
#include "rig/joint_mapping.h"

using namespace motionfork;
using namespace motionfork::pipeline;

namespace {

struct Frame {
  double unit;  // metres per file unit
  int axis;     // the file's up axis: 0 x, 1 y, 2 z
};

// Model frame (metres, Y up) -> the file's values: turned so that +Y becomes +axis, in units.
void ToFile(const float* p, const Frame& f, float* out) {
  double v[3] = {p[0], p[1], p[2]};
  if (f.axis == 2) v[0] = p[0], v[1] = -p[2], v[2] = p[1];  // Rx(+90): y -> z
  if (f.axis == 0) v[0] = p[1], v[1] = -p[0], v[2] = p[2];  // Rz(-90): y -> x
  for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(v[c] / f.unit);
}

// The first spelling of `role` in convention c, or "".
std::string NameOf(const RigConvention& c, const std::string& role) {
  const auto it = c.roles.find(role);
  return it == c.roles.end() || it->second.empty() || it->second[0].joints.size() != 1
             ? std::string()
             : it->second[0].joints[0];
}

// Where the mapping puts the Bandai joint of `role` when the rig is made from `walk`: the joint
// itself when the convention names the role, else made as DerivedRole says.
std::vector<float> Resolve(const RigConvention& c, const std::string& role, const Motion& walk,
                           const std::map<std::string, int>& joint_of_role) {
  const int T = walk.num_frames();
  std::vector<float> out(static_cast<size_t>(T) * 3, 0.0f);
  if (!NameOf(c, role).empty()) {
    const int j = joint_of_role.at(role);
    for (int t = 0; t < T; ++t)
      for (int a = 0; a < 3; ++a) out[3 * t + a] = walk.at(t, j)[a];
    return out;
  }
  for (const auto& [part, w] : DerivedRole(role)) {
    const std::vector<float> p = Resolve(c, part, walk, joint_of_role);
    for (size_t i = 0; i < out.size(); ++i) out[i] += static_cast<float>(w) * p[i];
  }
  return out;
}

double MaxDistance(const std::vector<float>& a, const std::vector<float>& b) {
  double worst = 0;
  for (size_t i = 0; i + 2 < a.size(); i += 3)
    worst = std::max(worst, std::sqrt(std::pow(double(a[i]) - b[i], 2) +
                                      std::pow(double(a[i + 1]) - b[i + 1], 2) +
                                      std::pow(double(a[i + 2]) - b[i + 2], 2)));
  return worst;
}

}  // namespace

TEST_CASE(
    "every built-in rig in every unit, up axis and rate maps, is told right and forecasts "
    "as the Bandai walk") {
  const auto bandai =
      LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons", "bandai")).skeleton;
  const std::vector<RigConvention> conventions = LoadRigConventions(MOTIONFORK_CONFIG_DIR);
  const std::vector<std::string> roles = RolesOfSkeleton(*bandai, conventions).roles;
  std::map<std::string, int> joint_of_role;
  for (int j = 0; j < bandai->num_joints(); ++j) joint_of_role[roles[j]] = j;
  const Forecaster forecaster =
      LoadForecaster(std::string(MOTIONFORK_SOURCE_DIR) + "/models/bandai");
  const int t_his = forecaster.config().generator.t_his;
  ForecastRequest request;
  request.k = 2;
  request.seed = 5;
  MotionInputOptions options;
  options.config_dir = MOTIONFORK_CONFIG_DIR;
  options.target_up = "y";
  const Frame frames[] = {{1, 1}, {0.01, 2}, {0.001, 0}, {0.0254, 2},
                          {1, 0}, {0.01, 1}, {0.001, 2}, {0.0254, 1},
                          {1, 2}, {0.01, 0}, {0.001, 1}, {0.0254, 0}};
  int cases = 0;
  long long compared = 0;  // values checked on the way back
  double worst_history = 0, worst_back = 0, worst_future = 0;
  for (const RigConvention& c : conventions) {
    // The rig: the convention's joints for the roles the Bandai skeleton has, each hanging from
    // the nearest ancestor it names, then a finger, a toe tip and a twist bone per side.
    std::vector<std::string> names;
    std::vector<int> parents, from;  // from: the Bandai joint (or, for extras, its parent's)
    std::vector<int> rig_of(bandai->num_joints(), -1);
    for (int j = 0; j < bandai->num_joints(); ++j) {
      const std::string name = NameOf(c, roles[j]);
      if (name.empty()) continue;
      int p = bandai->parent(j);
      while (p >= 0 && rig_of[p] < 0) p = bandai->parent(p);
      rig_of[j] = static_cast<int>(names.size());
      names.push_back(name);
      parents.push_back(p >= 0 ? rig_of[p] : -1);
      from.push_back(j);
    }
    const int role_joints = static_cast<int>(names.size());
    for (const char* side : {"l", "r"}) {
      const std::string s = side;
      for (const auto& [extra, role] : {std::pair<std::string, std::string>{"x_finger_", "wrist"},
                                        {"x_toe_tip_", "ankle"},
                                        {"x_twist_", "elbow"}}) {
        const int j = joint_of_role.at((s == "l" ? "left_" : "right_") + role);
        if (rig_of[j] < 0) continue;
        names.push_back(extra + s);
        parents.push_back(rig_of[j]);
        from.push_back(j);
      }
    }
    const auto rig =
        std::make_shared<const Skeleton>(Skeleton::FromParents(c.name, names, parents));
    for (const double rate : {24.0, 60.0, 120.0}) {
      DemoWalkOptions walk_options;
      walk_options.fps = rate;
      walk_options.frames = static_cast<int>(2 * rate);
      const Motion walk = MakeDemoWalk(bandai, walk_options);
      const int T = walk.num_frames();
      // The Bandai walk as the mapping makes it from this convention's joints.
      std::vector<float> expected(walk.positions().size());
      for (int j = 0; j < bandai->num_joints(); ++j) {
        const std::vector<float> p = Resolve(c, roles[j], walk, joint_of_role);
        for (int t = 0; t < T; ++t)
          for (int a = 0; a < 3; ++a)
            expected[(static_cast<size_t>(t) * bandai->num_joints() + j) * 3 + a] = p[3 * t + a];
      }
      const Motion reference = Resample(Motion(bandai, rate, expected), 30);
      const Forecast want = forecaster.Predict(reference, reference.num_frames() - t_his, request);
      for (const Frame& f : frames) {
        INFO(c.name << " at " << rate << " Hz, unit " << f.unit << " m, up axis " << f.axis);
        std::vector<float> file(static_cast<size_t>(T) * names.size() * 3);
        for (int t = 0; t < T; ++t) {
          for (size_t r = 0; r < names.size(); ++r) {
            float p[3];
            for (int a = 0; a < 3; ++a) p[a] = walk.at(t, from[r])[a];
            if (static_cast<int>(r) >= role_joints) {  // extras: 5 cm out from their parent
              p[0] += 0.03f, p[1] -= 0.04f;
            }
            ToFile(p, f, file.data() + (static_cast<size_t>(t) * names.size() + r) * 3);
          }
        }
        const Motion user(rig, rate, file);
        SkeletonConfig onto;
        onto.skeleton = onto.source = bandai;
        const ConformedMotion got = ConformForModel(user, {}, onto, options);
        ++cases;
        // Told right: the unit and up axis applied, the labels as they are.
        CHECK(got.frame.unit == Approx(f.unit).epsilon(1e-12));
        CHECK(got.frame.up_axis == f.axis);
        CHECK(got.frame.up_sign == 1);
        CHECK_FALSE(got.frame.swapped);
        // The way back: the file's own values at the joints read alone.
        const Motion back = FromModelFrame(got.motion, got.frame, got.roles);
        for (int j = 0; j < bandai->num_joints(); ++j) {
          const int s = got.source_of[j];
          if (s < 0) continue;
          for (int t = 0; t < T; ++t)
            for (int a = 0; a < 3; ++a, ++compared)
              worst_back = std::max(worst_back,
                                    f.unit * std::abs(double(back.at(t, j)[a]) - user.at(t, s)[a]));
        }
        // The history on the model, and its futures, as the Bandai walk's.
        const Motion mapped = Resample(got.motion, 30);
        const double h = MaxDistance(mapped.positions(), reference.positions());
        worst_history = std::max(worst_history, h);
        const Forecast f2 = forecaster.Predict(Motion(bandai, 30, mapped.positions()),
                                               mapped.num_frames() - t_his, request);
        worst_future = std::max(worst_future, MaxDistance(f2.futures, want.futures));
      }
    }
  }
  std::printf(
      "%d rigs x units x up axes x rates: the way back within %.2g m, the mapped history within "
      "%.2g m and the futures within %.2g m of the Bandai walk's\n",
      cases, worst_back, worst_history, worst_future);
  CHECK(cases == static_cast<int>(conventions.size()) * 3 * 12);
  CHECK(compared > cases * 100LL);
  CHECK(worst_back < 1e-5);
  CHECK(worst_history < 1e-5);
  CHECK(worst_future < 1e-4);
}
