#include "pipeline/predict_to_files.h"

#include <filesystem>
#include <map>

#include "core/error.h"
#include "core/text_format.h"
#include "io/prediction_file.h"
#include "pipeline/export_on_rig.h"
#include "pipeline/predict_text.h"

namespace motionfork::pipeline {

std::vector<std::string> OutputsInFolder(const std::string& folder,
                                         const std::vector<std::string>& histories) {
  std::vector<std::string> out;
  std::map<std::string, std::string> taken;  // name -> history
  for (const std::string& h : histories) {
    const std::string name = std::filesystem::path(h).stem().string();
    if (const auto it = taken.find(name); it != taken.end()) {
      throw FormatError(h + ": its output would be " + folder + "/" + name + " like " + it->second +
                        "'s; expected histories with different file names");
    }
    taken[name] = h;
    out.push_back((std::filesystem::path(folder) / name).string());
  }
  return out;
}

std::string PredictToFiles(const PredictFiles& files, const std::vector<std::string>& histories,
                           const std::string& out, int threads,
                           const std::function<void(double)>& progress) {
  const size_t n = histories.size();
  const std::vector<std::string> outs =
      n == 1 ? std::vector<std::string>{out} : OutputsInFolder(out, histories);
  std::vector<std::string> texts(n);
  size_t done = 0;
  PredictManyFromFiles(
      files, histories, threads, [&](int i, const Prediction& p, const PredictNotes& notes) {
        std::string& s = texts[static_cast<size_t>(i)];
        for (const std::string& note : notes.input) s += InputNoteLine(p.history, note) + "\n";
        if (notes.resampled_from > 0) {
          s += StringPrintf("note: resampled %s from %.6g Hz to the model's %.6g Hz\n",
                            p.history.c_str(), notes.resampled_from, p.fps);
        }
        s += HistoryDoubtsText(p);
        if (n > 1) std::filesystem::create_directories(out);
        const std::string base = WritePrediction(outs[i], p);
        s += PredictionRepairsText(p) + PredictionWrittenText(p, base, notes);
        // BASE_00.bvh ...: on the history's own rig when it is a BVH, else the model's.
        if (files.bvh)
          s += ExportSamples(p, base + ".json", base + ".bvh", -1, "history", {},
                             files.input.config_dir);
        if (progress) progress(static_cast<double>(++done) / n);
      });
  std::string report;
  for (const std::string& t : texts) report += t;
  return report;
}

}  // namespace motionfork::pipeline
