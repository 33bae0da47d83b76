#include "pipeline/motion_input.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/rig_config.h"
#include "core/error.h"
#include "core/resample.h"
#include "imputation/occlusion.h"
#include "io/motion_file.h"
#include "rig/body_frame.h"
#include "rig/joint_mapping.h"

namespace motionfork::pipeline {

std::vector<uint8_t> ConformMask(const Motion& motion, const std::vector<uint8_t>& missing,
                                 const SkeletonConfig& config) {
  // The mask as a motion of 0/1 "positions" goes through the same selection as the motion.
  const Motion as_motion(motion.skeleton_ptr(), motion.fps(),
                         std::vector<float>(missing.begin(), missing.end()));
  const Motion conformed = ConformToSkeleton(as_motion, config);
  std::vector<uint8_t> out(conformed.positions().size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = conformed.positions()[i] != 0.0f;
  return out;
}

namespace {

// A CSV names its skeleton (skeleton=NAME, as motionfork writes it) but stores no parents: the
// skeleton config of that name gives them when its joints are the file's (by name, any order).
// Returns the config, or nothing when there is none or its joints differ.
std::optional<SkeletonConfig> NamedSkeleton(const Motion& motion, const std::string& config_dir) {
  const Skeleton& s = motion.skeleton();
  if (!s.is_anonymous() || config_dir.empty() || s.name().empty()) return std::nullopt;
  const std::filesystem::path file =
      std::filesystem::path(config_dir) / "skeletons" / (s.name() + ".yaml");
  if (!std::filesystem::is_regular_file(file)) return std::nullopt;
  SkeletonConfig config = LoadSkeletonConfig(file.string());
  std::vector<std::string> have = s.joint_names();
  std::sort(have.begin(), have.end());
  for (const auto& candidate : {config.skeleton, config.source}) {
    std::vector<std::string> want = candidate->joint_names();
    std::sort(want.begin(), want.end());
    if (want == have) {
      SkeletonConfig onto;
      onto.path = config.path;
      onto.skeleton = onto.source = candidate;
      return onto;
    }
  }
  return std::nullopt;
}

// "A <- B, C <- D" for the target joints whose source is not the joint of the same name.
std::string MappingText(const Skeleton& to, const JointMapping& m) {
  std::string text;
  for (int j = 0; j < to.num_joints(); ++j) {
    const std::string& from = m.described[static_cast<size_t>(j)];
    if (from == to.joint_name(j)) continue;
    text += (text.empty() ? "" : ", ") + to.joint_name(j) + " <- " + from;
  }
  return text;
}

}  // namespace

std::string ProtocolUp(const std::string& config_dir, const std::string& protocol) {
  if (protocol.empty()) return "";
  try {
    return LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", protocol)).up;
  } catch (const FormatError&) {
    return "";  // a protocol this installation does not ship: nothing declared
  }
}

std::function<Motion(const Motion&, const SkeletonConfig&, double, std::vector<std::string>*)>
ConformClipsByRoles(const std::string& config_dir, const std::string& protocol) {
  MotionInputOptions options;
  options.config_dir = config_dir;
  options.target_up = ProtocolUp(config_dir, protocol);
  return [options](const Motion& motion, const SkeletonConfig& onto, double read_scale,
                   std::vector<std::string>* notes) {
    ConformedMotion c = ConformForModel(motion, {}, onto, options, read_scale);
    if (notes) *notes = std::move(c.notes);
    return Motion(onto.skeleton, c.motion.fps(), c.motion.positions());
  };
}

std::string InputNoteLine(const std::string& path, const std::string& note) {
  const std::string warning = "warning: ";
  if (note.rfind(warning, 0) == 0) return warning + path + ": " + note.substr(warning.size());
  return "note: " + path + ": " + note;
}

namespace {

// The motion (on the model's joints, named by a convention) in the model's frame, with a note on
// what was changed and the doubts as warnings.
void IntoModelFrame(ConformedMotion* c, const std::vector<RigConvention>& conventions,
                    const MotionInputOptions& options, double read_scale, bool unit_given) {
  std::vector<std::string> roles;
  try {
    roles = RolesOfSkeleton(c->motion.skeleton(), conventions).roles;
  } catch (const std::invalid_argument&) {
    return;  // a model skeleton no convention names: its frame cannot be checked
  }
  BodyFrameOptions o;
  o.read_scale = read_scale;
  o.unit = ParseLengthUnit(options.unit);
  if (o.unit == 0 && unit_given) o.unit = read_scale;
  o.up = options.up;
  o.left_right = options.left_right;
  o.target_up = options.target_up;
  const BodyFrame frame = DetectBodyFrame(c->motion, c->missing, roles, o);
  for (const std::string& w : frame.warnings) c->notes.push_back("warning: " + w);
  c->frame = frame;
  c->roles = roles;
  if (frame.IsIdentity(read_scale)) return;
  c->motion = ToModelFrame(c->motion, frame, roles, c->missing.empty() ? nullptr : &c->missing);
  c->notes.push_back("read as " + frame.Describe());
}

}  // namespace

ConformedMotion ConformForModel(const Motion& motion, const std::vector<uint8_t>& missing,
                                const SkeletonConfig& onto, const MotionInputOptions& options,
                                double read_scale, bool unit_given) {
  const Skeleton& have = motion.skeleton();
  const bool named = !(have.is_anonymous() && have.joint_name(0) == "j0");
  const std::vector<RigConvention> conventions = LoadRigConventions(options.config_dir);
  if (options.joint_map.empty() || !named) {
    std::optional<ConformedMotion> exact;
    try {
      ConformedMotion c;
      c.motion = ConformToSkeleton(motion, onto);
      if (!missing.empty()) c.missing = ConformMask(motion, missing, onto);
      exact = std::move(c);
    } catch (const std::invalid_argument&) {
      if (!named) throw;  // no names to map by: the count error says what fits
      // Other names: read them by their roles below.
    }
    if (exact) {
      for (const std::string& name : onto.skeleton->joint_names()) {
        const std::optional<int> j = have.is_anonymous() ? std::nullopt : have.Find(name);
        exact->source_of.push_back(j ? *j : -1);
      }
      IntoModelFrame(&*exact, conventions, options, read_scale, unit_given);
      return std::move(*exact);
    }
  }
  std::optional<RigConvention> forced;
  if (!options.joint_map.empty()) {
    forced = LoadRigConvention(ResolveConfigPath(options.config_dir, "rigs", options.joint_map));
  }
  const JointMapping m = MapJoints(have, *onto.skeleton, conventions, forced ? &*forced : nullptr);
  ConformedMotion out;
  out.motion = ApplyJointMapping(motion, m, onto.skeleton);
  for (const auto& sources : m.sources)
    out.source_of.push_back(sources.size() == 1 ? sources[0].first : -1);
  if (!missing.empty()) out.missing = ApplyJointMapping(missing, m);
  std::string note = "joints read as the " + m.source_rig + " rig onto skeleton '" +
                     onto.skeleton->name() + "' (" + std::to_string(onto.skeleton->num_joints()) +
                     " joints)";
  const std::string changed = MappingText(*onto.skeleton, m);
  if (!changed.empty()) note += ": " + changed;
  out.notes.push_back(note);
  if (!m.ignored.empty()) {
    std::string list;
    for (size_t i = 0; i < m.ignored.size() && i < 8; ++i) list += (i ? ", " : "") + m.ignored[i];
    if (m.ignored.size() > 8) list += ", ...";
    out.notes.push_back(std::to_string(m.ignored.size()) + " joint" +
                        (m.ignored.size() == 1 ? "" : "s") + " of the file not used: " + list);
  }
  IntoModelFrame(&out, conventions, options, read_scale, unit_given);
  return out;
}

LoadedMotion LoadMotionInput(const std::string& path, const MotionInputOptions& options,
                             std::vector<uint8_t>* missing) {
  LoadedMotion out;
  out.options = options;
  MotionReadOptions read;
  read.bvh.scale_to_metres = options.bvh_scale > 0 ? options.bvh_scale : 0.01;
  read.fps = options.fps > 0 ? options.fps : 30.0;
  if (!options.skeleton.empty()) {
    out.skeleton_config =
        LoadSkeletonConfig(ResolveConfigPath(options.config_dir, "skeletons", options.skeleton));
  }
  const MotionFormat format = FormatOfPath(path);
  read.missing = missing;
  out.motion = ReadMotionFile(path, read);
  if (format == MotionFormat::kNpy && options.fps <= 0) out.fps_assumed = true;
  if (format == MotionFormat::kBvh) {
    out.read_scale = read.bvh.scale_to_metres;
    out.unit_given = options.bvh_scale > 0;
  }
  if (!out.skeleton_config && format == MotionFormat::kCsv) {
    if (const auto named = NamedSkeleton(out.motion, options.config_dir)) {
      if (missing) *missing = ConformMask(out.motion, *missing, *named);
      out.motion = ConformToSkeleton(out.motion, *named);
    }
  }
  if (out.skeleton_config) {
    if (missing) *missing = ConformMask(out.motion, *missing, *out.skeleton_config);
    out.motion = ConformToSkeleton(out.motion, *out.skeleton_config);
  }
  return out;
}

ConformedMotion ConformLoadedMotion(const std::string& path, const LoadedMotion& lm,
                                    const std::vector<uint8_t>& missing,
                                    const std::shared_ptr<const Skeleton>& skeleton) {
  SkeletonConfig onto;
  onto.skeleton = skeleton;
  onto.source = lm.skeleton_config ? lm.skeleton_config->source : skeleton;
  if (lm.skeleton_config) onto.selection = lm.skeleton_config->selection;
  try {
    return ConformForModel(lm.motion, missing, onto, lm.options, lm.read_scale, lm.unit_given);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
}

MotionWithGaps LoadMotionWithGaps(const std::string& path, const MotionInputOptions& options,
                                  const std::shared_ptr<const Skeleton>& skeleton, double fps,
                                  const std::vector<std::string>& mask_specs, uint64_t seed) {
  std::vector<uint8_t> missing;
  const LoadedMotion lm = LoadMotionInput(path, options, &missing);
  ConformedMotion conformed = ConformLoadedMotion(path, lm, missing, skeleton);
  if (options.strict) {
    for (const std::string& note : conformed.notes) {
      if (note.rfind("warning: ", 0) == 0) {
        throw FormatError(path + ": " + note.substr(9) + " (--strict: refused)");
      }
    }
  }
  MotionWithGaps out{std::move(conformed.motion), std::move(conformed.missing), 0,
                     std::move(conformed.notes)};
  out.motion = Motion(skeleton, out.motion.fps(), out.motion.positions());
  if (std::abs(out.motion.fps() - fps) > 1e-6 * fps) {
    out.resampled_from = out.motion.fps();
    const Motion mask_motion(skeleton, out.motion.fps(),
                             std::vector<float>(out.missing.begin(), out.missing.end()));
    const Motion resampled_mask = Resample(mask_motion, fps);
    out.motion = Resample(out.motion, fps);
    out.missing.assign(resampled_mask.positions().size(), 0);
    for (size_t i = 0; i < out.missing.size(); ++i)
      out.missing[i] = resampled_mask.positions()[i] > 0.0f;
  }
  for (size_t k = 0; k < mask_specs.size(); ++k) {
    std::vector<uint8_t> m;
    try {
      m = MaskFromSpec(mask_specs[k], *skeleton, out.motion.num_frames(), seed + k);
    } catch (const std::invalid_argument& e) {
      throw FormatError(path + ": " + e.what());
    }
    for (size_t i = 0; i < m.size(); ++i) out.missing[i] |= m[i];
  }
  // Missing values hold 0 from here on (whatever the file or a mask covered).
  std::vector<float> pos = out.motion.positions();
  for (size_t i = 0; i < pos.size(); ++i) {
    if (out.missing[i]) pos[i] = 0.0f;
  }
  out.motion = Motion(skeleton, out.motion.fps(), std::move(pos));
  return out;
}

void RequireComplete(const std::string& path, const std::vector<uint8_t>& missing,
                     const std::string& what_next) {
  if (std::find(missing.begin(), missing.end(), 1) != missing.end()) {
    throw FormatError(path + ": has missing values; " + what_next);
  }
}

}  // namespace motionfork::pipeline
