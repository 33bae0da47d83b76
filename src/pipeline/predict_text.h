// `motionfork predict`'s report as text for people: how the history was repaired, what was written
// and how valid the futures are (pipeline/predict.h).
#pragma once

#include <string>

#include "io/prediction_file.h"
#include "pipeline/predict.h"

namespace motionfork::pipeline {

// The imputation and denoising of the history, one line each ("" when neither ran).
std::string PredictionRepairsText(const Prediction& p);

// One "warning: HISTORY: the history (frames A..B) is far from what the model knows: DOUBT" line
// per doubt of the gate ("" when none).
std::string HistoryDoubtsText(const Prediction& p);

// "wrote BASE.npy [K, T, J, 3] ... and BASE.json", then the futures' validity (angle ranges,
// prior NLL) as far as the bundle judged them (notes).
std::string PredictionWrittenText(const Prediction& p, const std::string& base,
                                  const PredictNotes& notes);

}  // namespace motionfork::pipeline
