// motionfork dataset stats: what a protocol makes of a data folder.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>

#include "app_common.h"
#include "commands.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"
#include "dataset/windows.h"
#include "dataset_loading.h"
#include "io/file_util.h"

namespace motionfork::app {
namespace {

struct StatsOptions {
  std::string protocol;
  std::string data;
  std::string split_file;
  std::string json;
};

struct SplitStats {
  int clips_listed = 0;  // clips the split assigns here (usable or skipped)
  int usable = 0;
  long long frames = 0;
  long long test_windows = 0;
  long long train_windows = 0;
  std::map<std::string, int> skipped;  // reason -> clips
};

Dataset LoadWithProgress(const std::string& protocol_name, const std::string& data,
                         const std::string& split_file, const GlobalOptions& g) {
  const std::string config_dir = ConfigDir(g.config_dir);
  const ProtocolOptions protocol =
      LoadProtocolConfig(ResolveConfigPath(config_dir, "protocols", protocol_name));
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(config_dir, "skeletons", protocol.skeleton));
  return LoadDatasetWithProgress(protocol, skeleton, data, split_file, g);
}

void RunStats(const StatsOptions& o, const GlobalOptions& g) {
  const Dataset ds = LoadWithProgress(o.protocol, o.data, o.split_file, g);
  const ProtocolOptions& p = ds.protocol;
  SplitStats stats[2];
  for (const Clip& c : ds.clips) {
    SplitStats& s = stats[c.split == Split::kTrain ? 0 : 1];
    const int T = c.motion.num_frames();
    s.clips_listed++;
    s.usable++;
    s.frames += T;
    s.test_windows += CountSlidingWindows(T, p.window_length(), p.test_stride, p.test_include_last);
    s.train_windows += std::max(0, T - p.window_length() + 1);
  }
  std::map<std::string, int> skipped_unsplit;
  for (const SkippedClip& c : ds.skipped) {
    if (c.split.empty()) {
      skipped_unsplit[c.reason]++;
      continue;
    }
    SplitStats& s = stats[c.split == "train" ? 0 : 1];
    s.clips_listed++;
    s.skipped[c.reason]++;
  }
  int total = 0;
  for (const auto& grp : ds.groups) total += grp.second;

  std::printf("protocol:  %s (%s)\n", p.name.c_str(), p.path.c_str());
  std::printf(
      "           %.6g Hz, t_his %d + t_pred %d = %d frames, root %s, skeleton %s (%d joints)\n",
      p.fps, p.t_his, p.t_pred, p.window_length(), ToString(p.root),
      ds.skeleton.skeleton->name().c_str(), ds.skeleton.skeleton->num_joints());
  std::printf("data:      %s (%s in %s)\n", o.data.c_str(),
              ds.from_cache ? "from the cache" : "parsed", Duration(ds.seconds_reading).c_str());
  std::printf("sources:  ");
  for (size_t i = 0; i < ds.groups.size(); ++i) {
    std::printf("%s %s %s clips", i ? " +" : "", ds.groups[i].first.c_str(),
                WithThousands(ds.groups[i].second).c_str());
  }
  std::printf(" = %s clips\n", WithThousands(total).c_str());
  std::printf("split:     %s train, %s test%s\n", WithThousands(stats[0].clips_listed).c_str(),
              WithThousands(stats[1].clips_listed).c_str(),
              p.split_file.empty() && o.split_file.empty() ? " (by subject)" : " (split file)");
  std::printf("\n%-6s %8s %8s %12s %12s %14s %16s\n", "split", "clips", "usable", "frames",
              "duration", "test windows", "train windows");
  for (int k = 0; k < 2; ++k) {
    const SplitStats& s = stats[k];
    std::printf("%-6s %8s %8s %12s %12s %14s %16s\n", k == 0 ? "train" : "test",
                WithThousands(s.clips_listed).c_str(), WithThousands(s.usable).c_str(),
                WithThousands(s.frames).c_str(), Duration(s.frames / p.fps).c_str(),
                WithThousands(s.test_windows).c_str(), WithThousands(s.train_windows).c_str());
  }
  std::printf("\ntest windows: stride %d, %s; train windows: every start (random sampling)\n",
              p.test_stride,
              p.test_include_last ? "last start included" : "DLow's rule (last start excluded)");
  for (int k = 0; k < 2; ++k) {
    for (const auto& [reason, n] : stats[k].skipped) {
      std::printf("skipped (%s): %s clips %s\n", k == 0 ? "train" : "test",
                  WithThousands(n).c_str(), reason.c_str());
    }
  }
  for (const auto& [reason, n] : skipped_unsplit) {
    std::printf("skipped: %s clips %s\n", WithThousands(n).c_str(), reason.c_str());
  }
  if (!ds.split_missing.empty()) {
    std::printf("warning: %s clips named by the split file were not found (first: %s)\n",
                WithThousands(ds.split_missing.size()).c_str(), ds.split_missing.front().c_str());
  }
  if (!o.json.empty()) {
    std::string j = "{\"protocol\": \"" + p.name + "\", \"fps\": " + std::to_string(p.fps) +
                    ", \"t_his\": " + std::to_string(p.t_his) +
                    ", \"t_pred\": " + std::to_string(p.t_pred) +
                    ", \"clips\": " + std::to_string(total) + ", \"sources\": {";
    for (size_t i = 0; i < ds.groups.size(); ++i) {
      j += (i ? ", \"" : "\"") + ds.groups[i].first + "\": " + std::to_string(ds.groups[i].second);
    }
    j += "}";
    for (int k = 0; k < 2; ++k) {
      const SplitStats& s = stats[k];
      j += std::string(", \"") + (k == 0 ? "train" : "test") +
           "\": {\"clips\": " + std::to_string(s.clips_listed) +
           ", \"usable\": " + std::to_string(s.usable) +
           ", \"frames\": " + std::to_string(s.frames) +
           ", \"test_windows\": " + std::to_string(s.test_windows) +
           ", \"train_windows\": " + std::to_string(s.train_windows) +
           ", \"skipped\": " + std::to_string(s.clips_listed - s.usable) + "}";
    }
    j += ", \"split_missing\": " + std::to_string(ds.split_missing.size()) + "}\n";
    WriteFileAtomically(o.json, j);
  }
}

}  // namespace

void AddDatasetCommand(CLI::App& app, GlobalOptions& global) {
  CLI::App* dataset = app.add_subcommand("dataset", "Datasets under a protocol");
  dataset->require_subcommand(1);
  auto o = std::make_shared<StatsOptions>();
  CLI::App* stats = dataset->add_subcommand(
      "stats",
      "Clips, frames and windows per split of a data folder under a protocol.\n"
      "The first run parses the files and writes a cache; later runs read the cache.");
  stats
      ->add_option("--protocol", o->protocol, "Protocol name (bandai, h36m, humaneva) or YAML path")
      ->required();
  stats
      ->add_option("--data", o->data,
                   "Data folder (Bandai: the folder with the .tar.xz archives or unpacked .bvh; "
                   "H36M/HumanEva: the output of tools/videopose3d_to_motionfork.py)")
      ->required()
      ->check(CLI::ExistingDirectory);
  stats->add_option("--split", o->split_file, "Split file overriding the protocol's split.file");
  stats->add_option("--json", o->json, "Also write every figure to this JSON file");
  stats->callback([o, &global] { RunStats(*o, global); });
}

}  // namespace motionfork::app
