// A protocol's dataset: every clip read from the source files, mapped to the protocol skeleton,
// resampled to the protocol frame rate, labelled, and split into train/test, with the clips the
// protocol leaves out listed with their reason.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/motion.h"
#include "core/skeleton_config.h"
#include "dataset/protocol_options.h"

namespace motionfork {

enum class Split { kTrain, kTest };
const char* ToString(Split split);

struct Clip {
  std::string
      name;  // file name without extension ("dataset-2_walk_elderly_001"), or subject/action
  std::string group;    // source it came from (archive or folder name, or the subject)
  std::string subject;  // H36M subject, Bandai style; may be empty
  std::string action;   // H36M action, Bandai content; may be empty
  Split split = Split::kTrain;
  Motion motion;  // protocol skeleton, protocol fps, metres, world coordinates
};

struct SkippedClip {
  std::string name;
  std::string group;
  std::string reason;  // "shorter than 75 frames", "dropped take", "not in split file", ...
  int frames = 0;      // after resampling
  std::string split;   // "train"/"test" when known, else ""
};

struct Dataset {
  ProtocolOptions protocol;
  SkeletonConfig skeleton;
  std::vector<Clip> clips;  // usable clips
  std::vector<SkippedClip> skipped;
  std::vector<std::pair<std::string, int>> groups;  // source -> clips read from it, in order
  std::vector<std::string> split_missing;           // named by the split file but not found
  bool from_cache = false;
  double seconds_reading = 0;  // wall time to get the raw clips (parse or cache)

  std::vector<int> ClipIndices(Split split) const;
  // Frame counts of the given clips (for windows).
  std::vector<int> ClipFrames(const std::vector<int>& indices) const;
};

// The clips a model trains on from windows of `window` frames: the training split's clips of at
// least that many frames, in order, and the whole clips held out of them (for per-epoch figures):
// round(share x clips), at least 1, drawn by seed. Throws std::invalid_argument "<who>: expected at
// least 2 training clips of >= <window> frames, found <n>".
struct HeldOutClips {
  std::vector<int> clips;
  std::set<int> held_out;
};
HeldOutClips HoldOutTrainingClips(const Dataset& dataset, int window, double share, uint64_t seed,
                                  const std::string& who);

struct LoadProgress {
  std::string stage;   // "reading BVH", "reading cache", ...
  double fraction;     // 0..1
  std::string detail;  // current file
};

struct DatasetLoadOptions {
  std::string cache_dir;   // "" = no cache
  std::string split_file;  // overrides the protocol's split.file; "" = protocol's
  std::function<void(const LoadProgress&)> progress;  // may be empty
  // Problems the load carries on after (a damaged cache is rebuilt, an unwritable cache folder is
  // not used); may be empty.
  std::function<void(const std::string&)> warning;
};

// data_dir: the folder the protocol's source format reads (see configs/protocols/README.md).
// Throws FormatError naming the file for unreadable input, std::invalid_argument for a folder
// holding nothing the protocol can read.
Dataset LoadDataset(const ProtocolOptions& protocol, const SkeletonConfig& skeleton,
                    const std::string& data_dir, const DatasetLoadOptions& options = {});

}  // namespace motionfork
