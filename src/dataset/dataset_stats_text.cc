#include "dataset/dataset_stats_text.h"

#include <utility>

#include "core/text_format.h"

namespace motionfork {
namespace {

void AppendSplits(std::string* s, const DatasetStats& stats, double fps) {
  StringAppendf(s, "\n%-6s %8s %8s %12s %12s %14s %16s\n", "split", "clips", "usable", "frames",
                "duration", "test windows", "train windows");
  for (const auto& [name, split] : {std::pair{"train", &stats.train}, {"test", &stats.test}}) {
    StringAppendf(s, "%-6s %8s %8s %12s %12s %14s %16s\n", name,
                  WithThousands(split->clips_listed).c_str(), WithThousands(split->usable).c_str(),
                  WithThousands(split->frames).c_str(), Duration(split->frames / fps).c_str(),
                  WithThousands(split->test_windows).c_str(),
                  WithThousands(split->train_windows).c_str());
  }
}

}  // namespace

std::string DatasetStatsText(const Dataset& ds, const DatasetStats& stats,
                             const std::string& data_dir, bool split_file_given) {
  const ProtocolOptions& p = ds.protocol;
  std::string text;
  StringAppendf(&text, "protocol:  %s (%s)\n", p.name.c_str(), p.path.c_str());
  StringAppendf(
      &text,
      "           %.6g Hz, t_his %d + t_pred %d = %d frames, root %s, skeleton %s (%d joints)\n",
      p.fps, p.t_his, p.t_pred, p.window_length(), ToString(p.root),
      ds.skeleton.skeleton->name().c_str(), ds.skeleton.skeleton->num_joints());
  StringAppendf(&text, "data:      %s (%s in %s)\n", data_dir.c_str(),
                ds.from_cache ? "from the cache" : "parsed", Duration(ds.seconds_reading).c_str());
  StringAppendf(&text, "sources:  ");
  for (size_t i = 0; i < ds.groups.size(); ++i) {
    StringAppendf(&text, "%s %s %s clips", i ? " +" : "", ds.groups[i].first.c_str(),
                  WithThousands(ds.groups[i].second).c_str());
  }
  StringAppendf(&text, " = %s clips\n", WithThousands(stats.clips).c_str());
  StringAppendf(&text, "split:     %s train, %s test%s\n",
                WithThousands(stats.train.clips_listed).c_str(),
                WithThousands(stats.test.clips_listed).c_str(),
                !split_file_given ? " (by subject)" : " (split file)");
  AppendSplits(&text, stats, p.fps);
  StringAppendf(&text,
                "\ntest windows: stride %d, %s; train windows: every start (random sampling)\n",
                p.test_stride,
                p.test_include_last ? "last start included" : "DLow's rule (last start excluded)");
  for (const auto& [name, s] : {std::pair{"train", &stats.train}, {"test", &stats.test}}) {
    for (const auto& [reason, n] : s->skipped) {
      StringAppendf(&text, "skipped (%s): %s clips %s\n", name, WithThousands(n).c_str(),
                    reason.c_str());
    }
  }
  for (const auto& [reason, n] : stats.skipped_unsplit) {
    StringAppendf(&text, "skipped: %s clips %s\n", WithThousands(n).c_str(), reason.c_str());
  }
  if (!ds.split_missing.empty()) {
    StringAppendf(&text, "warning: %s clips named by the split file were not found (first: %s)\n",
                  WithThousands(ds.split_missing.size()).c_str(), ds.split_missing.front().c_str());
  }
  return text;
}

}  // namespace motionfork
