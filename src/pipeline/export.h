// A prediction's samples as BVH files (joint rotations on a rest pose), for animation tools.
// What `motionfork export` and the C++ API write.
#pragma once

#include <string>
#include <vector>

#include "io/bvh_writer.h"
#include "io/prediction_file.h"

namespace motionfork::pipeline {

struct ExportedSample {
  int sample = 0;
  std::string text;      // the BVH file's text
  double deviation = 0;  // metres: the largest joint distance from the prediction to what a
                         // BVH reader gets back (fixed bone lengths move joints a little)
};

// Sample k of p (history + its future) as BVH text. `source` names the prediction in errors (a
// non-finite value names the sample, frame and joint). Throws FormatError / std::invalid_argument.
ExportedSample ExportSample(const Prediction& p, const std::string& source, int k,
                            const BvhWriteOptions& options);

// OUT.bvh -> OUT_07.bvh for sample 7 of `count` (digits: at least 2, enough for count - 1).
std::string NumberedPath(const std::string& out, int k, int count);

// Every sample (or only `sample` when >= 0) of p as BVH text, all made before anything is written
// so bad input writes nothing; then each file is written atomically. Paths: `out` for one sample,
// NumberedPath(out, ...) for all. Returns what was written, with its path in `written`.
struct WrittenSample {
  ExportedSample sample;
  std::string path;
};
std::vector<WrittenSample> ExportPrediction(const Prediction& p, const std::string& source,
                                            const std::string& out, int sample,
                                            const BvhWriteOptions& options);

}  // namespace motionfork::pipeline
