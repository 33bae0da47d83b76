#include "dataset/dataset.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <random>
#include <regex>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/joint_selection.h"
#include "core/resample.h"
#include "dataset/split_file.h"
#include "io/archive.h"
#include "io/bvh.h"
#include "io/clip_cache.h"
#include "io/npy.h"
#include "io/videopose3d.h"

namespace motionfork {

namespace fs = std::filesystem;

const char* ToString(Split split) { return split == Split::kTrain ? "train" : "test"; }

std::vector<int> Dataset::ClipIndices(Split split) const {
  std::vector<int> out;
  for (size_t c = 0; c < clips.size(); ++c) {
    if (clips[c].split == split) out.push_back(static_cast<int>(c));
  }
  return out;
}

HeldOutClips HoldOutTrainingClips(const Dataset& dataset, int window, double share, uint64_t seed,
                                  const std::string& who) {
  HeldOutClips out;
  for (int c : dataset.ClipIndices(Split::kTrain)) {
    if (dataset.clips[c].motion.num_frames() >= window) out.clips.push_back(c);
  }
  if (out.clips.size() < 2) {
    throw std::invalid_argument(
        who + ": expected at least 2 training clips of >= " + std::to_string(window) +
        " frames, found " + std::to_string(out.clips.size()));
  }
  std::vector<int> order = out.clips;
  std::shuffle(order.begin(), order.end(), std::mt19937_64(seed));
  const size_t held = std::max<size_t>(1, static_cast<size_t>(std::lround(share * order.size())));
  out.held_out.insert(order.begin(), order.begin() + held);
  return out;
}

std::vector<int> Dataset::ClipFrames(const std::vector<int>& indices) const {
  std::vector<int> out;
  out.reserve(indices.size());
  for (int c : indices) out.push_back(clips.at(c).motion.num_frames());
  return out;
}

namespace {

// Bumped whenever parsing changes what ends up in a cache.
constexpr int kReaderVersion = 1;

bool HasSuffix(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string Stem(const std::string& path) { return fs::path(path).stem().string(); }

// What the raw reading depends on: files, sizes, modification times, reading options.
struct SourceFiles {
  std::vector<std::string> files;  // sorted
  bool archives = false;
  uint64_t key = 0;
};

uint64_t KeyOf(const ProtocolOptions& p, const std::vector<std::string>& files,
               const std::string& data_dir) {
  std::ostringstream s;
  s << "v" << kReaderVersion << "|" << ToString(p.format) << "|" << p.unit_scale << "|"
    << p.skeleton;
  for (const std::string& f : files) {
    std::error_code ec;
    const auto size = fs::file_size(f, ec);
    const auto time = fs::last_write_time(f, ec).time_since_epoch().count();
    s << "|" << fs::relative(f, data_dir, ec).string() << ":" << size << ":" << time;
  }
  return Fnv1a64(s.str());
}

SourceFiles FindSources(const ProtocolOptions& p, const std::string& data_dir) {
  SourceFiles src;
  if (!fs::is_directory(data_dir)) {
    throw std::invalid_argument("data folder '" + data_dir + "' does not exist or is not a folder");
  }
  if (p.format == SourceFormat::kVideoPose3d) {
    const fs::path manifest = fs::path(data_dir) / "manifest.tsv";
    if (!fs::is_regular_file(manifest)) {
      throw std::invalid_argument("data folder '" + data_dir + "' has no manifest.tsv; protocol '" +
                                  p.name + "' reads VideoPose3D data converted with " +
                                  "tools/videopose3d_to_motionfork.py INPUT.npz " + data_dir);
    }
    src.files.push_back(manifest.string());
    for (const VideoPose3dTake& t : ReadVideoPose3dManifest(data_dir)) src.files.push_back(t.path);
  } else {
    std::vector<std::string> bvh, archives;
    for (const auto& e : fs::recursive_directory_iterator(
             data_dir, fs::directory_options::follow_directory_symlink)) {
      if (!e.is_regular_file()) continue;
      const std::string path = e.path().string();
      std::string lower = path;
      std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
      if (HasSuffix(lower, ".bvh")) {
        bvh.push_back(path);
      } else if (LooksLikeArchive(lower)) {
        archives.push_back(path);
      }
    }
    if (bvh.empty() && archives.empty()) {
      throw std::invalid_argument("data folder '" + data_dir + "' holds no .bvh files and no " +
                                  "archives of them; protocol '" + p.name + "' reads BVH");
    }
    src.archives = bvh.empty();
    src.files = bvh.empty() ? archives : bvh;
    std::sort(src.files.begin(), src.files.end());
  }
  src.key = KeyOf(p, src.files, data_dir);
  return src;
}

std::vector<CachedClip> ReadRawClips(const ProtocolOptions& p, const SkeletonConfig& skel,
                                     const std::string& data_dir, const SourceFiles& src,
                                     const DatasetLoadOptions& options) {
  std::vector<CachedClip> raw;
  auto report = [&](const std::string& stage, double f, const std::string& detail) {
    if (options.progress) options.progress(LoadProgress{stage, f, detail});
  };
  if (p.format == SourceFormat::kVideoPose3d) {
    const auto takes = ReadVideoPose3dManifest(data_dir);
    for (size_t i = 0; i < takes.size(); ++i) {
      const VideoPose3dTake& t = takes[i];
      Motion m = ReadNpyMotion(t.path, skel.source, t.fps);
      if (p.unit_scale != 1.0) {
        std::vector<float> pos = m.positions();
        for (float& v : pos) v = static_cast<float>(v * p.unit_scale);
        m = Motion(m.skeleton_ptr(), m.fps(), std::move(pos));
      }
      raw.push_back(
          CachedClip{t.subject + "/" + t.action, t.subject, t.subject, t.action, std::move(m)});
      report("reading takes", double(i + 1) / takes.size(), t.subject + "/" + t.action);
    }
    return raw;
  }
  BvhOptions bvh;
  bvh.scale_to_metres = p.unit_scale;
  const size_t n = src.files.size();
  for (size_t i = 0; i < n; ++i) {
    const std::string& file = src.files[i];
    if (src.archives) {
      const std::string group = fs::path(file).filename().string();
      ForEachArchiveFile(
          file,
          [](const std::string& entry) {
            std::string lower = entry;
            std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
            return HasSuffix(lower, ".bvh");
          },
          [&](const std::string& entry, std::string_view bytes) {
            raw.push_back(CachedClip{Stem(entry), group, "", "",
                                     ReadBvhText(bytes, file + ":" + entry, bvh)});
          },
          [&](double f) { report("reading BVH archives", (i + f) / n, group); });
    } else {
      std::error_code ec;
      const fs::path rel = fs::relative(file, data_dir, ec);
      const std::string group = rel.has_parent_path() ? rel.begin()->string() : ".";
      raw.push_back(CachedClip{Stem(file), group, "", "", ReadBvhFile(file, bvh)});
      report("reading BVH files", double(i + 1) / n, Stem(file));
    }
  }
  return raw;
}

void Warn(const DatasetLoadOptions& options, const std::string& message) {
  if (options.warning) options.warning(message);
}

// A damaged cache is a warning and is rebuilt, never fatal.
bool ReadCacheOrWarn(const std::string& path, uint64_t key, const DatasetLoadOptions& options,
                     std::vector<CachedClip>* raw) {
  try {
    return ReadClipCache(path, key, raw);
  } catch (const FormatError& e) {
    raw->clear();
    Warn(options, std::string(e.what()) + "; reading the data again and rebuilding the cache");
    return false;
  }
}

// An unwritable cache folder is a warning: the run carries on without a cache.
void WriteCacheOrWarn(const std::string& path, uint64_t key, const std::vector<CachedClip>& raw,
                      const DatasetLoadOptions& options) {
  try {
    WriteClipCache(path, key, raw);
  } catch (const std::exception& e) {
    Warn(options, std::string(e.what()) + "; carrying on without a dataset cache");
  }
}

}  // namespace

Dataset LoadDataset(const ProtocolOptions& protocol, const SkeletonConfig& skeleton,
                    const std::string& data_dir, const DatasetLoadOptions& options) {
  ValidateProtocol(protocol);
  Dataset ds;
  ds.protocol = protocol;
  ds.skeleton = skeleton;
  const auto start = std::chrono::steady_clock::now();
  const SourceFiles src = FindSources(protocol, data_dir);

  std::vector<CachedClip> raw;
  std::string cache_path;
  if (!options.cache_dir.empty()) {
    char name[64];
    std::snprintf(name, sizeof(name), "%s-%016llx.clips", protocol.name.c_str(),
                  static_cast<unsigned long long>(src.key));
    cache_path = (fs::path(options.cache_dir) / name).string();
    if (options.progress) options.progress(LoadProgress{"reading cache", 0, cache_path});
    ds.from_cache = ReadCacheOrWarn(cache_path, src.key, options, &raw);
  }
  if (!ds.from_cache) {
    raw = ReadRawClips(protocol, skeleton, data_dir, src, options);
    if (!cache_path.empty()) WriteCacheOrWarn(cache_path, src.key, raw, options);
  }
  ds.seconds_reading =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // Split: a file naming clips, or subject lists.
  std::map<std::string, std::string> split_of;
  if (!protocol.split_file.empty() || !options.split_file.empty()) {
    std::string path = options.split_file.empty() ? protocol.split_file : options.split_file;
    if (options.split_file.empty() && fs::path(path).is_relative())
      path = (fs::path(data_dir) / path).string();
    if (!fs::is_regular_file(path)) {
      throw std::invalid_argument("split file '" + path + "' not found (protocol '" +
                                  protocol.name +
                                  "' expects it in the data folder; pass --split FILE otherwise)");
    }
    split_of = ReadSplitFile(path);
  }
  const std::set<std::string> train(protocol.train_subjects.begin(), protocol.train_subjects.end());
  const std::set<std::string> test(protocol.test_subjects.begin(), protocol.test_subjects.end());
  const std::set<std::pair<std::string, std::string>> dropped(protocol.drop_takes.begin(),
                                                              protocol.drop_takes.end());
  std::optional<std::regex> labels;
  if (!protocol.label_pattern.empty()) labels.emplace(protocol.label_pattern);

  const JointSelection target =
      skeleton.selection ? *skeleton.selection : JointSelection{*skeleton.skeleton, {}};
  std::set<std::string> seen;
  for (CachedClip& rc : raw) {
    if (ds.groups.empty() || ds.groups.back().first != rc.group)
      ds.groups.emplace_back(rc.group, 0);
    ds.groups.back().second++;
    seen.insert(rc.name);
    Clip clip;
    clip.name = rc.name;
    clip.group = rc.group;
    clip.subject = rc.subject;
    clip.action = rc.action;
    std::smatch m;
    if (labels && std::regex_match(rc.name, m, *labels)) {
      if (protocol.label_action_group > 0) clip.action = m[protocol.label_action_group];
      if (protocol.label_subject_group > 0) clip.subject = m[protocol.label_subject_group];
    }
    SkippedClip skip{clip.name, clip.group, "", rc.motion.num_frames(), ""};
    std::string split;
    if (!split_of.empty()) {
      auto it = split_of.find(rc.name);
      if (it != split_of.end()) split = it->second;
    } else if (train.count(clip.subject)) {
      split = "train";
    } else if (test.count(clip.subject)) {
      split = "test";
    }
    skip.split = split;
    if (split.empty()) {
      skip.reason = split_of.empty() ? "subject not in the split" : "not in the split file";
      ds.skipped.push_back(std::move(skip));
      continue;
    }
    clip.split = split == "train" ? Split::kTrain : Split::kTest;
    if (dropped.count({clip.subject, clip.action})) {
      skip.reason = "dropped take";
      ds.skipped.push_back(std::move(skip));
      continue;
    }
    Motion motion = ApplySelection(rc.motion, target);
    if (std::abs(motion.fps() - protocol.fps) > 1e-6 * protocol.fps) {
      motion = Resample(motion, protocol.fps);
    }
    rc.motion = Motion();  // release the raw frames early
    if (motion.num_frames() < protocol.min_length) {
      skip.frames = motion.num_frames();
      skip.reason = "shorter than " + std::to_string(protocol.min_length) + " frames";
      ds.skipped.push_back(std::move(skip));
      continue;
    }
    clip.motion = std::move(motion);
    ds.clips.push_back(std::move(clip));
  }
  for (const auto& [name, split] : split_of) {
    if (!seen.count(name)) ds.split_missing.push_back(name);
  }
  return ds;
}

}  // namespace motionfork
