#include "dataset/dataset_stats_json.h"

#include <nlohmann/json.hpp>

namespace motionfork {
namespace {

using json = nlohmann::ordered_json;

json SplitJson(const SplitStats& s) {
  return {{"clips", s.clips_listed},
          {"usable", s.usable},
          {"frames", s.frames},
          {"test_windows", s.test_windows},
          {"train_windows", s.train_windows},
          {"skipped", s.clips_listed - s.usable}};
}

}  // namespace

json DatasetStatsJson(const Dataset& ds, const DatasetStats& stats) {
  const ProtocolOptions& p = ds.protocol;
  json sources = json::object();
  for (const auto& [source, clips] : ds.groups) sources[source] = clips;
  return {{"protocol", p.name},
          {"fps", p.fps},
          {"t_his", p.t_his},
          {"t_pred", p.t_pred},
          {"clips", stats.clips},
          {"sources", sources},
          {"train", SplitJson(stats.train)},
          {"test", SplitJson(stats.test)},
          {"split_missing", ds.split_missing.size()}};
}

}  // namespace motionfork
