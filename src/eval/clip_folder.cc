#include "eval/clip_folder.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <optional>
#include <regex>
#include <stdexcept>

#include "core/resample.h"
#include "io/motion_file.h"

namespace motionfork {

namespace fs = std::filesystem;

ClipFolder LoadClipFolder(const ProtocolOptions& protocol, const SkeletonConfig& skeleton,
                          const std::string& dir, const ClipFolderOptions& options) {
  ValidateProtocol(protocol);
  if (!fs::is_directory(dir)) {
    throw std::invalid_argument("clips folder '" + dir + "' does not exist or is not a folder");
  }
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".bvh" || ext == ".npy" || ext == ".csv") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    throw std::invalid_argument(
        "clips folder '" + dir +
        "' holds no motion file (.bvh, .npy or .csv, searched recursively)");
  }
  MotionReadOptions read;
  read.skeleton = skeleton.skeleton;
  read.fps = options.default_fps > 0 ? options.default_fps : protocol.fps;
  read.bvh.scale_to_metres = protocol.unit_scale;
  std::optional<std::regex> labels;
  if (!protocol.label_pattern.empty()) labels.emplace(protocol.label_pattern);

  ClipFolder out;
  for (size_t i = 0; i < files.size(); ++i) {
    const std::string& file = files[i];
    if (options.progress) {
      options.progress(LoadProgress{"reading clips", double(i) / files.size(), file});
    }
    Clip clip;
    clip.name = fs::path(file).stem().string();
    std::error_code ec;
    const fs::path rel = fs::relative(file, dir, ec);
    clip.group = rel.has_parent_path() ? rel.begin()->string() : ".";
    clip.split = Split::kTest;
    std::smatch m;
    if (labels && std::regex_match(clip.name, m, *labels)) {
      if (protocol.label_action_group > 0) clip.action = m[protocol.label_action_group];
      if (protocol.label_subject_group > 0) clip.subject = m[protocol.label_subject_group];
    }
    Motion motion;
    try {
      if (options.conform) {
        const bool bvh = FormatOfPath(file) == MotionFormat::kBvh;
        std::vector<std::string> notes;
        motion = options.conform(ReadMotionFile(file, read), skeleton,
                                 bvh ? read.bvh.scale_to_metres : 1.0, &notes);
        for (const std::string& n : notes)
          if (n.rfind("warning: ", 0) == 0) out.warnings.push_back(file + ": " + n.substr(9));
      } else {
        motion = ConformToSkeleton(ReadMotionFile(file, read), skeleton);
      }
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(file + ": " + e.what());
    }
    if (std::abs(motion.fps() - protocol.fps) > 1e-6 * protocol.fps) {
      motion = Resample(motion, protocol.fps);
    }
    const int min_length = protocol.min_length > 0 ? protocol.min_length : protocol.window_length();
    if (motion.num_frames() < min_length) {
      out.skipped.push_back(SkippedClip{clip.name, clip.group,
                                        "shorter than " + std::to_string(min_length) + " frames",
                                        motion.num_frames(), "test"});
      continue;
    }
    clip.motion = std::move(motion);
    out.clips.push_back(std::move(clip));
  }
  if (options.progress) options.progress(LoadProgress{"reading clips", 1.0, ""});
  return out;
}

}  // namespace motionfork
