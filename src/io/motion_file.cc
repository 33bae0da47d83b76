#include "io/motion_file.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "core/enum_names.h"
#include "io/csv.h"
#include "io/npy.h"

namespace motionfork {

MotionFormat FormatOfPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  if (ext == ".bvh") return MotionFormat::kBvh;
  if (ext == ".npy") return MotionFormat::kNpy;
  if (ext == ".csv") return MotionFormat::kCsv;
  throw std::invalid_argument("'" + path + "': unknown motion format '" + ext +
                              "'; expected .bvh, .npy or .csv");
}

const char* ToString(MotionFormat format) {
  static constexpr EnumName<MotionFormat> kNames[] = {
      {MotionFormat::kBvh, "BVH"}, {MotionFormat::kNpy, "NumPy .npy"}, {MotionFormat::kCsv, "CSV"}};
  return NameOf(format, kNames);
}

Motion ReadMotionFile(const std::string& path, const MotionReadOptions& options) {
  switch (FormatOfPath(path)) {
    case MotionFormat::kBvh: {
      Motion m = ReadBvhFile(path, options.bvh);
      if (options.missing) options.missing->assign(m.positions().size(), 0);
      return m;
    }
    case MotionFormat::kNpy:
      return ReadNpyMotion(path, options.skeleton, options.fps, options.missing);
    case MotionFormat::kCsv:
      return ReadCsvMotion(path, options.skeleton, options.fps, options.missing);
  }
  throw std::logic_error("unreachable");
}

void WriteMotionFile(const std::string& path, const Motion& motion, const BvhWriteOptions& bvh) {
  switch (FormatOfPath(path)) {
    case MotionFormat::kBvh:
      return WriteBvh(path, motion, bvh);
    case MotionFormat::kNpy:
      return WriteNpyMotion(path, motion);
    case MotionFormat::kCsv:
      return WriteCsvMotion(path, motion);
  }
}

}  // namespace motionfork
