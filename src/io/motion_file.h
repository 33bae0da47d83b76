// Reading and writing a motion file of any supported format, chosen by extension:
// .bvh, .npy and .csv (read and write).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/motion.h"
#include "io/bvh.h"
#include "io/bvh_writer.h"

namespace motionfork {

enum class MotionFormat { kBvh, kNpy, kCsv };

// From the file name's extension (case-insensitive). Throws std::invalid_argument naming the file
// and the supported extensions.
MotionFormat FormatOfPath(const std::string& path);
const char* ToString(MotionFormat format);

struct MotionReadOptions {
  // Joints of .npy files (which store none) and expected joints of .csv files; may be null, then
  // an anonymous skeleton (npy) or one named by the CSV header is used.
  std::shared_ptr<const Skeleton> skeleton;
  // Frame rate for formats that may not store one (.npy always, .csv without an fps comment).
  double fps = 30.0;
  BvhOptions bvh;
  // When set, missing values are accepted (NaN in .npy; empty, nan or NaN fields in .csv; BVH
  // has none): they read as 0 and are marked 1 here, [T, J, 3] like the positions.
  std::vector<uint8_t>* missing = nullptr;
};

Motion ReadMotionFile(const std::string& path, const MotionReadOptions& options = {});

// All-or-nothing write. BVH: joint rotations fitted to the positions (io/bvh_writer.h), which
// needs a skeleton with parents; `bvh` sets its unit (centimetres by default, as ReadMotionFile
// reads), rotation order and fit.
void WriteMotionFile(const std::string& path, const Motion& motion,
                     const BvhWriteOptions& bvh = {});

}  // namespace motionfork
