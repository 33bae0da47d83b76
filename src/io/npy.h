// NumPy .npy arrays (format versions 1.0, 2.0 and 3.0) of float32 or float64, little-endian,
// C order. Read as float32; written as float32 ('<f4', version 1.0).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/motion.h"

namespace motionfork {

struct NpyArray {
  std::vector<int64_t> shape;
  std::vector<float> data;  // C order
};

// Throws FormatError naming the file, what was expected and what was found (bad magic, unsupported
// dtype or Fortran order, truncated data, NaN/Inf at a given index).
// allow_nan: NaN values are kept (missing values); Inf is still an error.
NpyArray ReadNpy(const std::string& path, bool allow_nan = false);
NpyArray ParseNpy(std::string_view bytes, const std::string& source_name, bool allow_nan = false);
// All-or-nothing write (temporary file + rename). Throws std::invalid_argument when the shape does
// not match the data size.
void WriteNpy(const std::string& path, const NpyArray& array);
std::string SerializeNpy(const NpyArray& array);

// A [T, J, 3] array as a motion of the given skeleton (its joint count must equal J) at fps Hz.
// With a null skeleton an anonymous J-joint skeleton is used. With `missing`, NaN values are
// accepted: they read as 0 and are marked 1 in *missing ([T, J, 3]).
Motion ReadNpyMotion(const std::string& path, std::shared_ptr<const Skeleton> skeleton, double fps,
                     std::vector<uint8_t>* missing = nullptr);
void WriteNpyMotion(const std::string& path, const Motion& motion);

}  // namespace motionfork
