#include "pipeline/export_on_rig.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/resample.h"
#include "io/bvh_rig.h"
#include "io/file_util.h"
#include "io/motion_file.h"
#include "pipeline/export.h"
#include "pipeline/motion_input.h"
#include "pipeline/rig_solve.h"

namespace motionfork::pipeline {
namespace {

double Distance(const float* a, const float* b) {
  return std::sqrt(std::pow(double(a[0]) - b[0], 2) + std::pow(double(a[1]) - b[1], 2) +
                   std::pow(double(a[2]) - b[2], 2));
}

// Sample k of p in the file's values ([T, J, 3] file units, the file's axes and labels).
std::vector<double> SampleInFile(const Prediction& p, int k, const UserRig& user) {
  const size_t size = static_cast<size_t>(p.frames()) * p.joints() * 3;
  const Motion sample(p.skeleton, p.fps, std::vector<float>(p.sample(k), p.sample(k) + size));
  const Motion back = user.roles.empty() ? sample : FromModelFrame(sample, user.frame, user.roles);
  std::vector<double> out(size);
  for (size_t i = 0; i < size; ++i) out[i] = back.positions()[i] / user.read_scale;
  return out;
}

}  // namespace

UserRig ReadUserRig(const std::string& path, const Prediction& p, const std::string& config_dir) {
  if (FormatOfPath(path) != MotionFormat::kBvh) {
    throw FormatError(path +
                      ": expected a .bvh file to take the rig from (its hierarchy and "
                      "frames); a .npy or .csv stores no rig");
  }
  const HistoryReading r = p.reading.value_or(HistoryReading{});
  MotionInputOptions in;
  in.skeleton = r.skeleton;
  in.joint_map = r.joint_map;
  in.unit = r.unit;
  in.up = r.up;
  in.left_right = r.left_right;
  in.bvh_scale = r.bvh_scale;
  in.fps = r.fps;
  in.config_dir = config_dir;
  in.target_up = ProtocolUp(config_dir, p.protocol);
  const LoadedMotion lm = LoadMotionInput(path, in);
  const ConformedMotion c = ConformLoadedMotion(path, lm, {}, p.skeleton);
  UserRig u;
  u.path = path;
  BvhOptions bvh;
  bvh.scale_to_metres = lm.read_scale;
  ReadBvhFile(path, bvh, &u.rig);
  u.frame = c.frame;
  u.roles = c.roles;
  u.read_scale = lm.read_scale;
  u.on_model = c.motion.positions();
  u.model_joints = c.motion.num_joints();
  const Skeleton& read = lm.motion.skeleton();
  int carried = 0;
  for (int j = 0; j < p.joints(); ++j) {
    const int s = j < static_cast<int>(c.source_of.size()) ? c.source_of[j] : -1;
    int node = -1;
    for (size_t n = 0; s >= 0 && n < u.rig.nodes.size(); ++n) {
      if (!u.rig.nodes[n].end_site && u.rig.nodes[n].name == read.joint_name(s))
        node = static_cast<int>(n);
    }
    u.node_of.push_back(node);
    carried += node >= 0;
  }
  if (carried == 0) {
    throw FormatError(path + ": none of its joints carries one of the model's (" +
                      p.skeleton->name() +
                      "); expected the file the prediction's history came from");
  }
  return u;
}

RigSample ExportSampleOnRig(const Prediction& p, int k, const UserRig& user) {
  const BvhRig& rig = user.rig;
  const int J = p.joints(), T = p.frames();
  const double fm = p.fps, fu = rig.fps;
  RigSample out;
  out.sample = k;
  out.fps = fu;
  // The prediction's history against the file's, read again and resampled as predict did.
  const Motion on_model =
      Resample(Motion(p.skeleton, fu, user.on_model), fm);  // fu: the file's rate
  if (p.start_frame + p.t_his > on_model.num_frames()) {
    throw FormatError(user.path + ": the prediction's history (frames " +
                      std::to_string(p.start_frame) + ".." +
                      std::to_string(p.start_frame + p.t_his - 1) + " at " +
                      std::to_string(static_cast<int>(fm)) + " Hz) lies outside the file (" +
                      std::to_string(on_model.num_frames()) +
                      " frames at that rate); expected the file the history came from");
  }
  for (int t = 0; t < p.t_his; ++t)
    for (int j = 0; j < J; ++j) {
      const float* a = on_model.at(p.start_frame + t, j);
      const float* b = p.sample(k) + (static_cast<size_t>(t) * J + j) * 3;
      out.history_mismatch = std::max(out.history_mismatch, Distance(a, b));
    }

  // The history's own frames, unchanged.
  const double t_first = p.start_frame / fm, t_end = (p.start_frame + p.t_his - 1) / fm;
  const int u_first = static_cast<int>(std::ceil(t_first * fu - 1e-6));
  const int u_last =
      std::min(static_cast<int>(std::floor(t_end * fu + 1e-6)), rig.num_frames() - 1);
  std::vector<double> values(rig.frame(u_first), rig.frame(u_last) + rig.num_channels);
  out.history_frames = u_last - u_first + 1;

  // The future at the file's rate, joints the model predicts solved, the rest held.
  const std::vector<double> want = SampleInFile(p, k, user);
  std::vector<uint8_t> targeted(rig.nodes.size(), 0);
  for (int j = 0; j < J; ++j)
    if (user.node_of[j] >= 0) targeted[static_cast<size_t>(user.node_of[j])] = 1;
  out.solved_joints = static_cast<int>(std::count(targeted.begin(), targeted.end(), 1));
  for (const BvhRig::Node& n : rig.nodes) out.held_joints += !n.end_site;
  out.held_joints -= out.solved_joints;
  const RigSolver solver(rig, targeted);
  std::vector<double> frame(rig.frame(u_last), rig.frame(u_last) + rig.num_channels);
  std::vector<double> targets(3 * rig.nodes.size(), 0.0);
  const double metres_per_unit = user.read_scale * user.frame.scale;
  const double t_stop = t_end + p.t_pred / fm;
  for (int n = 1; (u_last + n) / fu <= t_stop + 1e-9; ++n) {
    const double x = (p.t_his - 1) + ((u_last + n) / fu - t_end) * fm;
    const int i0 = std::min(static_cast<int>(std::floor(x)), T - 1), i1 = std::min(i0 + 1, T - 1);
    const double a = x - i0;
    for (int j = 0; j < J; ++j) {
      const int node = user.node_of[j];
      if (node < 0) continue;
      for (int c = 0; c < 3; ++c) {
        targets[3 * node + c] = (1 - a) * want[(static_cast<size_t>(i0) * J + j) * 3 + c] +
                                a * want[(static_cast<size_t>(i1) * J + j) * 3 + c];
      }
    }
    solver.Solve(targets, frame.data());
    out.displacement =
        std::max(out.displacement, solver.Miss(targets, frame.data()) * metres_per_unit);
    values.insert(values.end(), frame.begin(), frame.end());
    ++out.future_frames;
  }
  out.text = BvhRigText(rig, values, rig.frame_time);
  return out;
}

RigChoice RigSource(const Prediction& p, const std::string& choice, const std::string& source) {
  if (choice == "model") return {};
  if (choice != "history") return {choice, ""};
  std::string ext = std::filesystem::path(p.history).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  if (ext != ".bvh") return {};  // a .npy or .csv history has no rig
  const std::string fallback = "; written on the model's skeleton (pass --rig FILE.bvh to use it)";
  if (!p.reading) {
    return {"", "note: " + source + ": it does not record how its history " + p.history +
                    " was read (written before 2026-12-05)" + fallback};
  }
  // The file as named when it is the one recorded (or the recorded one is gone), else the
  // recorded one: a same-named file in another folder is not taken for it.
  namespace fs = std::filesystem;
  const std::string& recorded = p.reading->path;
  const bool named = fs::is_regular_file(p.history);
  const bool kept = !recorded.empty() && fs::is_regular_file(recorded);
  std::error_code ec;
  if (named && (!kept || fs::equivalent(p.history, recorded, ec))) return {p.history, ""};
  if (kept) return {recorded, ""};
  return {"", "note: " + source + ": its history " +
                  (p.reading->path.empty() ? p.history : p.reading->path) + " is not found" +
                  fallback};
}

std::vector<WrittenRigSample> ExportPredictionOnRig(const Prediction& p, const UserRig& user,
                                                    const std::string& out, int sample) {
  if (sample >= p.k) {
    throw std::invalid_argument("--sample " + std::to_string(sample) + ": the prediction holds " +
                                "samples 0.." + std::to_string(p.k - 1));
  }
  std::vector<WrittenRigSample> written;
  for (int k = 0; k < p.k; ++k) {
    if (sample >= 0 && sample != k) continue;
    written.push_back(
        {ExportSampleOnRig(p, k, user), sample >= 0 ? out : NumberedPath(out, k, p.k)});
  }
  for (const WrittenRigSample& w : written) WriteFileAtomically(w.path, w.sample.text);
  return written;
}

}  // namespace motionfork::pipeline
