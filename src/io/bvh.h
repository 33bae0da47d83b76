// BVH (Biovision Hierarchy) reading: hierarchy, per-joint channels, forward kinematics.
//
// Handles any channel count (0..6) and order per joint; position channels, where present, are the
// joint's local translation and replace the matching OFFSET component (Bandai files carry 6
// channels on every joint); rotation channels compose in the order they are listed (intrinsic:
// "Zrotation Xrotation Yrotation" means R = Rz * Rx * Ry), angles in degrees. End Sites are read
// and, on request, kept as joints named "<parent>_End". Windows (CRLF) line endings are accepted.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/motion.h"

namespace motionfork {

struct BvhOptions {
  // File length unit -> metres. BVH carries no unit; 0.01 reads centimetres (Bandai and most
  // optical mocap exports).
  double scale_to_metres = 0.01;
  // Keep End Sites as extra joints ("<parent>_End").
  bool include_end_sites = false;
};

// A BVH file's own hierarchy and channel values, for writing motion back onto the same rig
// (io/bvh_rig.h): what the positions are computed from.
struct BvhRig {
  struct Node {
    std::string name;  // an End Site: "<parent>_End"
    int parent = -1;   // node index, -1 for the root
    bool end_site = false;
    double offset[3] = {0, 0, 0};  // file units
    // Channel kinds in file order: 0..2 X/Y/Z position, 3..5 X/Y/Z rotation (degrees).
    std::vector<int> channels;
    int first_channel = 0;  // index of its first value in a frame
  };
  std::vector<Node> nodes;     // ROOT, JOINTs and End Sites in file (depth-first) order
  int num_channels = 0;        // values per frame
  double frame_time = 0;       // seconds, as in the file
  double fps = 0;              // as ReadBvhText reports it
  std::vector<double> values;  // [frames, num_channels]
  int num_frames() const {
    return num_channels ? static_cast<int>(values.size() / num_channels) : 0;
  }
  const double* frame(int t) const { return values.data() + static_cast<size_t>(t) * num_channels; }
};

// Reads a BVH file and returns world positions [T, J, 3] in metres; fps = 1 / Frame Time, snapped
// to an integer n when within 1e-3 Hz of it, or when Frame Time is 1/n rounded to the decimals it
// was printed with and the rates agree within 0.1% (0.008333 -> 120 Hz, 0.0333333 -> 30 Hz; 0.03
// stays 33.33 Hz). Throws FormatError naming the file, line
// (header) or frame (motion data), what was expected and what was found.
// `rig`, when given, receives the file's hierarchy and channel values.
Motion ReadBvhFile(const std::string& path, const BvhOptions& options = {}, BvhRig* rig = nullptr);

// The same from text already in memory (e.g. read from an archive); source_name is used in errors.
Motion ReadBvhText(std::string_view text, const std::string& source_name,
                   const BvhOptions& options = {}, BvhRig* rig = nullptr);

}  // namespace motionfork
