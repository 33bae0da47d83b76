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

#include "core/motion.h"

namespace motionfork {

struct BvhOptions {
  // File length unit -> metres. BVH carries no unit; 0.01 reads centimetres (Bandai and most
  // optical mocap exports).
  double scale_to_metres = 0.01;
  // Keep End Sites as extra joints ("<parent>_End").
  bool include_end_sites = false;
};

// Reads a BVH file and returns world positions [T, J, 3] in metres; fps = 1 / Frame Time, snapped
// to an integer n when within 1e-3 Hz of it, or when Frame Time is 1/n rounded to the decimals it
// was printed with and the rates agree within 0.1% (0.008333 -> 120 Hz, 0.0333333 -> 30 Hz; 0.03
// stays 33.33 Hz). Throws FormatError naming the file, line
// (header) or frame (motion data), what was expected and what was found.
Motion ReadBvhFile(const std::string& path, const BvhOptions& options = {});

// The same from text already in memory (e.g. read from an archive); source_name is used in errors.
Motion ReadBvhText(std::string_view text, const std::string& source_name,
                   const BvhOptions& options = {});

}  // namespace motionfork
