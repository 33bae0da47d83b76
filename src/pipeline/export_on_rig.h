// Futures on the user's own rig: a predicted sample written as a BVH of the skeleton the history
// came in (its joint names, hierarchy, rest offsets and channels, its unit and axes, its frame
// rate). The history's own frames come first, unchanged, so the clip plays on; then the future,
// resampled to the file's rate, with the rotations of the joints the model predicts solved
// (pipeline/rig_solve.h) and every other joint (fingers, toes, twist bones) held at its last
// history pose. Bones stay rigid; how far that leaves a joint from where the model put it is
// reported.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "io/bvh.h"
#include "io/bvh_writer.h"
#include "io/prediction_file.h"
#include "rig/body_frame.h"

namespace motionfork::pipeline {

// The history file's rig and how its values were put on the model (as `predict` did).
struct UserRig {
  std::string path;
  BvhRig rig;
  std::vector<int> node_of;  // [model joint] -> the rig node it is read from alone, -1 for none
  BodyFrame frame;           // the file's frame (unit, up axis, left/right) against the model's
  std::vector<std::string> roles;  // the model joints' roles ([] when no convention names them)
  double read_scale = 0.01;        // metres per file unit the values were read with
  // The file on the model's joints and frame, at the file's rate ([T, J, 3] metres): what the
  // prediction's history was resampled from.
  std::vector<float> on_model;
  int model_joints = 0;
};

// Reads the BVH `path` as `predict` read the prediction's history (p.reading, the configs in
// config_dir, the model's skeleton and protocol from p). Throws FormatError naming the file when
// it is no BVH, cannot be read, or no joint of it carries a model joint.
UserRig ReadUserRig(const std::string& path, const Prediction& p, const std::string& config_dir);

struct RigSample {
  int sample = 0;
  std::string text;  // the BVH file
  int history_frames = 0, future_frames = 0;
  double fps = 0;
  int solved_joints = 0, held_joints = 0;  // the rig's joints posed from the model / held
  // Metres: the largest distance of a solved joint from where the model put it (rigid bones),
  // and of the file's history, read again, from the prediction's (0 unless the file changed or
  // the history was repaired).
  double displacement = 0, history_mismatch = 0;
};

// Sample k of p (history + its future) on `user`'s rig. Throws FormatError naming the file when
// the prediction's history frames lie outside it.
RigSample ExportSampleOnRig(const Prediction& p, int k, const UserRig& user);

// Where `export --rig CHOICE` takes the rig from: "model" -> none (the model's own skeleton), a
// .bvh path -> it, "history" -> the prediction's history file when it was a BVH (its absolute
// path as recorded, else as named), read the way predict read it (p.reading). `note` says why a
// BVH history's rig is not used (not found; a prediction that does not record its reading).
struct RigChoice {
  std::string path;  // "" = the model's skeleton
  std::string note;  // "" or a "note: ..." line for people
};
RigChoice RigSource(const Prediction& p, const std::string& choice, const std::string& source);

// Every sample of p (or only `sample` when >= 0) on `user`'s rig, all made before anything is
// written; each file then written atomically: `out` for one sample, NumberedPath(out, ...) for
// all (pipeline/export.h).
struct WrittenRigSample {
  RigSample sample;
  std::string path;
};
std::vector<WrittenRigSample> ExportPredictionOnRig(const Prediction& p, const UserRig& user,
                                                    const std::string& out, int sample);

// "wrote OUT_00.bvh: sample 0 on the rig of FILE (N joints: A posed from the model, B held),
// H history + F future frames at R Hz, in centimetres, Z up; largest joint displacement from the
// prediction X mm" (and a warning when the file's history no longer matches the prediction's).
std::string RigSampleText(const WrittenRigSample& w, const UserRig& user, const Prediction& p);

// `export`'s whole job: every sample of p (or `sample`) written as BVH on the rig RigSource(p,
// rig_choice) names (ExportPredictionOnRig), else on the model's skeleton with `options`
// (ExportPrediction); returns the report, a line per file (and the choice's note). `source`
// names the prediction in errors and notes. Throws std::invalid_argument for an `out` not ending
// in .bvh or bad options.
std::string ExportSamples(const Prediction& p, const std::string& source, const std::string& out,
                          int sample, const std::string& rig_choice, const BvhWriteOptions& options,
                          const std::string& config_dir);

}  // namespace motionfork::pipeline
