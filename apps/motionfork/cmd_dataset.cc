// motionfork dataset stats: what a protocol makes of a data folder.
#include <nlohmann/json.hpp>

#include "app_common.h"
#include "commands.h"
#include "dataset/dataset_stats.h"
#include "dataset/dataset_stats_json.h"
#include "dataset/dataset_stats_text.h"
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

void RunStats(const StatsOptions& o, const GlobalOptions& g) {
  const Dataset ds = LoadProtocolDataset(o.protocol, o.data, o.split_file, g);
  const ProtocolOptions& p = ds.protocol;
  const DatasetStats stats = ComputeDatasetStats(ds);
  PrintText(DatasetStatsText(ds, stats, o.data, !p.split_file.empty() || !o.split_file.empty()));
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
