// `motionfork predict`'s whole job: one or many history files -> their predictions written as
// prediction files (io/prediction_file.h) -> the report to print.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "pipeline/predict.h"

namespace motionfork::pipeline {

// Output bases for several histories written into `folder`: folder/<file name without its
// extension>. Throws FormatError naming both files when two histories share a name.
std::vector<std::string> OutputsInFolder(const std::string& folder,
                                         const std::vector<std::string>& histories);

// One history: OUT.npy + OUT.json. Several: the folder OUT (made when absent) with OUT/NAME.npy +
// OUT/NAME.json per history (OutputsInFolder), each the prediction of that file alone, made by up
// to `threads` threads (PredictManyFromFiles). Nothing is written when a history cannot be used.
// Returns the report, history by history in the order given: resampling notes, repairs, files
// written and the futures' validity. progress(share of histories done) may be empty.
std::string PredictToFiles(const PredictFiles& files, const std::vector<std::string>& histories,
                           const std::string& out, int threads,
                           const std::function<void(double)>& progress = {});

}  // namespace motionfork::pipeline
