// A folder of a user's own motion files, read under a protocol's settings, as test clips
// (`motionfork eval --clips DIR`).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/skeleton_config.h"
#include "dataset/dataset.h"
#include "dataset/protocol_options.h"

namespace motionfork {

struct ClipFolder {
  std::vector<Clip> clips;            // split kTest, protocol skeleton and fps, metres
  std::vector<SkippedClip> skipped;   // too short for the protocol
  std::vector<std::string> warnings;  // "FILE: text": doubts of ClipFolderOptions::conform
};

// Puts a file's motion (as read: BVH lengths at `read_scale` metres per unit) on the protocol
// skeleton `onto`; notes for people go to `notes`, those starting "warning: " being doubts.
using ClipConform = std::function<Motion(const Motion& motion, const SkeletonConfig& onto,
                                         double read_scale, std::vector<std::string>* notes)>;

struct ClipFolderOptions {
  // Frame rate of files that store none (.npy; .csv without an fps comment), Hz; 0 = the
  // protocol's.
  double default_fps = 0;
  std::function<void(const LoadProgress&)> progress;  // may be empty
  // How a file's joints reach the skeleton; empty: ConformToSkeleton (by names, or by count for
  // .npy). pipeline::ConformClipsByRoles also maps other rigs by their joints' roles and turns
  // them into the protocol's frame (unit, up axis, left/right).
  ClipConform conform;
};

// Every .bvh, .npy and .csv file under dir (recursively, in path order). Each is mapped onto the
// protocol skeleton (ConformToSkeleton: by joint names, or by joint count for .npy), resampled to
// the protocol frame rate, labelled with the protocol's label pattern when its name matches, and
// skipped when shorter than the protocol's minimum length. BVH lengths are scaled by the
// protocol's unit_scale. Throws std::invalid_argument when dir holds no motion file, FormatError
// (naming the file) for unreadable ones, std::invalid_argument naming the file when a file's
// joints do not fit the skeleton.
ClipFolder LoadClipFolder(const ProtocolOptions& protocol, const SkeletonConfig& skeleton,
                          const std::string& dir, const ClipFolderOptions& options = {});

}  // namespace motionfork
