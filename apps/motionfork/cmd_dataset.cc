// motionfork dataset stats: what a protocol makes of a data folder.
#include <cstdio>
#include <nlohmann/json.hpp>

#include "app_common.h"
#include "commands.h"
#include "dataset/dataset_stats.h"
#include "dataset/dataset_stats_json.h"
#include "experiment_common.h"
#include "flags.h"

namespace motionfork::app {
namespace {

struct StatsOptions {
  std::string protocol;
  std::string data;
  std::string split_file;
  std::string json;
};

void PrintSplits(const DatasetStats& stats, double fps) {
  std::printf("\n%-6s %8s %8s %12s %12s %14s %16s\n", "split", "clips", "usable", "frames",
              "duration", "test windows", "train windows");
  for (const auto& [name, s] : {std::pair{"train", &stats.train}, {"test", &stats.test}}) {
    std::printf("%-6s %8s %8s %12s %12s %14s %16s\n", name, WithThousands(s->clips_listed).c_str(),
                WithThousands(s->usable).c_str(), WithThousands(s->frames).c_str(),
                Duration(s->frames / fps).c_str(), WithThousands(s->test_windows).c_str(),
                WithThousands(s->train_windows).c_str());
  }
}

void RunStats(const StatsOptions& o, const GlobalOptions& g) {
  const Dataset ds = LoadProtocolDataset(o.protocol, o.data, o.split_file, g);
  const ProtocolOptions& p = ds.protocol;
  const DatasetStats stats = ComputeDatasetStats(ds);
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
  std::printf(" = %s clips\n", WithThousands(stats.clips).c_str());
  std::printf("split:     %s train, %s test%s\n", WithThousands(stats.train.clips_listed).c_str(),
              WithThousands(stats.test.clips_listed).c_str(),
              p.split_file.empty() && o.split_file.empty() ? " (by subject)" : " (split file)");
  PrintSplits(stats, p.fps);
  std::printf("\ntest windows: stride %d, %s; train windows: every start (random sampling)\n",
              p.test_stride,
              p.test_include_last ? "last start included" : "DLow's rule (last start excluded)");
  for (const auto& [name, s] : {std::pair{"train", &stats.train}, {"test", &stats.test}}) {
    for (const auto& [reason, n] : s->skipped) {
      std::printf("skipped (%s): %s clips %s\n", name, WithThousands(n).c_str(), reason.c_str());
    }
  }
  for (const auto& [reason, n] : stats.skipped_unsplit) {
    std::printf("skipped: %s clips %s\n", WithThousands(n).c_str(), reason.c_str());
  }
  if (!ds.split_missing.empty()) {
    std::printf("warning: %s clips named by the split file were not found (first: %s)\n",
                WithThousands(ds.split_missing.size()).c_str(), ds.split_missing.front().c_str());
  }
  EmitJson(o.json, DatasetStatsJson(ds, stats));
}

}  // namespace

void AddDatasetCommand(CLI::App& app, GlobalOptions& global) {
  CLI::App* dataset = app.add_subcommand("dataset", "Datasets under a protocol");
  dataset->require_subcommand(1);
  const auto [stats, o] = AddSubcommand<StatsOptions>(
      dataset, global, RunStats, "stats",
      R"(Clips, frames and windows per split of a data folder under a protocol.
The first run parses the files and writes a cache; later runs read the cache.)");
  stats
      ->add_option("--protocol", o->protocol, "Protocol name (bandai, h36m, humaneva) or YAML path")
      ->required();
  AddDataOption(stats, &o->data,
                "Data folder (Bandai: the folder with the .tar.xz archives or unpacked .bvh; "
                "H36M/HumanEva: the output of tools/videopose3d_to_motionfork.py)");
  stats->add_option("--split", o->split_file, "Split file overriding the protocol's split.file");
  AddJsonOption(stats, &o->json, "Every figure");
}

}  // namespace motionfork::app
