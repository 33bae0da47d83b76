// Reading a motion for a model: the file (BVH, NumPy, CSV) with its missing values, put on the
// model's skeleton and frame rate, with extra missing values from mask specs. Every command that
// reads a motion (predict, check, impute, denoise, ood, prior score, render, info, convert) and
// the C++ API go through here, so a motion means the same thing everywhere.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "config/skeleton_config.h"
#include "core/motion.h"
#include "core/skeleton.h"
#include "rig/body_frame.h"

namespace motionfork::pipeline {

// How to read a motion file (the commands' --skeleton, --fps, --bvh-scale).
struct MotionInputOptions {
  std::string skeleton;  // skeleton config name or YAML path; "" = as stored in the file
  double fps = 0;        // Hz, for files that store none; 0 = 30 Hz for those
  // BVH length unit in metres; 0 = read as centimetres (0.01), the unit then checked against the
  // body's size when the motion is put on a model (ConformForModel). > 0: that unit, not checked.
  double bvh_scale = 0;
  std::string config_dir;  // the configs folder `skeleton` is looked up in
  // How a file whose joint names are not the model's maps onto it: "" = the rig convention
  // (configs/rigs/) that explains the file's names; else a convention name or a joint map YAML.
  std::string joint_map;
  // The file's frame on the way onto a model (rig/body_frame.h): "" = detected from the body.
  std::string unit;        // "m", "cm", "mm", "in" (metres per unit as the file stores them)
  std::string up;          // "y", "z", "x", "-y", "-z", "-x": the file's up axis
  std::string left_right;  // "as-labelled" or "swapped"
  // The model's up axis (its protocol's `up`, ProtocolUp); "" = a motion keeps its own.
  std::string target_up;
  // A doubt about the motion on the way onto a model (a "warning: " note: upside down, left/right
  // exchanged, no human size) is an error instead (FormatError naming the file).
  bool strict = false;
};

// The `up` of protocol `protocol` (a name in config_dir/protocols or a path); "" when the protocol
// declares none or its config is not there.
std::string ProtocolUp(const std::string& config_dir, const std::string& protocol);

struct LoadedMotion {
  Motion motion;
  std::optional<SkeletonConfig> skeleton_config;  // when MotionInputOptions::skeleton was given
  bool fps_assumed = false;    // the file stores no frame rate and none was given
  MotionInputOptions options;  // as it was read (its joint map applies to later mappings)
  // Metres per file unit the values were read with (0.01 for a BVH by default, else 1), and
  // whether that unit was given (--bvh-scale) rather than assumed.
  double read_scale = 1.0;
  bool unit_given = false;
};

// Reads the file; with options.skeleton, puts it on that skeleton (selection, re-ordering). With
// `missing`, missing values are accepted (NaN in .npy, empty or nan in .csv) and marked there,
// [T, J, 3] on the loaded motion's joints. Throws FormatError naming the file.
LoadedMotion LoadMotionInput(const std::string& path, const MotionInputOptions& options,
                             std::vector<uint8_t>* missing = nullptr);

// A missing-value mask [T, J, 3] following a motion through ConformToSkeleton: a value of the
// result is missing when any value it was made from was.
std::vector<uint8_t> ConformMask(const Motion& motion, const std::vector<uint8_t>& missing,
                                 const SkeletonConfig& config);

// A motion (and its missing-value mask, [T, J, 3], or empty) put on `onto`'s skeleton: by the
// skeleton's own joint names (ConformToSkeleton) when the motion has them, else by the roles of
// its joints (rig/joint_mapping.h) under the conventions of options.config_dir/rigs or
// options.joint_map (which, when given, is always used); then in the model's frame (metres, Y up,
// left/right as the body says: rig/body_frame.h; options.unit/up/left_right force them).
// read_scale: metres per file unit the values were read with; unit_given: that unit is the
// file's (not checked). `notes` say what was done, for people; those starting "warning: " are
// doubts about the input. Throws std::invalid_argument saying which joints or roles are missing.
struct ConformedMotion {
  Motion motion;
  std::vector<uint8_t> missing;
  std::vector<std::string> notes;
  // The way back (futures on the file's own rig, pipeline/export_on_rig.h): [model joint] -> the
  // file's joint it is read from alone (-1: a blend of several, or not by name); the frame the
  // values were turned from (FromModelFrame, with `roles` of the model's joints; roles empty:
  // values kept as read).
  std::vector<int> source_of;
  BodyFrame frame;
  std::vector<std::string> roles;
};
ConformedMotion ConformForModel(const Motion& motion, const std::vector<uint8_t>& missing,
                                const SkeletonConfig& onto, const MotionInputOptions& options,
                                double read_scale = 1.0, bool unit_given = false);

// A motion read by LoadMotionInput (lm.options: how) put on `skeleton` by ConformForModel, its
// skeleton config's selection applied; an error names `path`.
ConformedMotion ConformLoadedMotion(const std::string& path, const LoadedMotion& lm,
                                    const std::vector<uint8_t>& missing,
                                    const std::shared_ptr<const Skeleton>& skeleton);

// For a folder of a user's clips (`eval --clips`, eval/clip_folder.h ClipConform): each file's
// motion onto the protocol skeleton as ConformForModel puts a history on a model -- by joint
// names, else by the roles of its rig -- and into the protocol's frame (`up` of `protocol` in
// config_dir; unit and left/right told from the body).
std::function<Motion(const Motion&, const SkeletonConfig&, double, std::vector<std::string>*)>
ConformClipsByRoles(const std::string& config_dir, const std::string& protocol);

// "note: PATH: TEXT" or, for a note starting "warning: ", "warning: PATH: TEXT".
std::string InputNoteLine(const std::string& path, const std::string& note);

// A motion on a model's skeleton and frame rate, with its missing values.
struct MotionWithGaps {
  Motion motion;                   // [T, J, 3] metres; missing values hold 0
  std::vector<uint8_t> missing;    // [T, J, 3], 1 = missing
  double resampled_from = 0;       // Hz of the file when it was resampled to the model's, else 0
  std::vector<std::string> notes;  // how its joints were mapped (ConformForModel), for people
};

// Reads `path` (missing values allowed), maps it onto `skeleton` by joint names (or the
// selection of options.skeleton) and resamples it to `fps` Hz; the masks of `mask_specs`
// (random:SHARE, joints:A,B[@FIRST-LAST], a .npy file; imputation/occlusion.h) are added, random
// ones seeded with seed + their index. Throws FormatError naming the file.
MotionWithGaps LoadMotionWithGaps(const std::string& path, const MotionInputOptions& options,
                                  const std::shared_ptr<const Skeleton>& skeleton, double fps,
                                  const std::vector<std::string>& mask_specs = {},
                                  uint64_t seed = 0);

// Throws FormatError naming `path` and `what_next` when `missing` marks any value.
void RequireComplete(const std::string& path, const std::vector<uint8_t>& missing,
                     const std::string& what_next);

}  // namespace motionfork::pipeline
