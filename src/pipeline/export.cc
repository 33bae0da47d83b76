#include "pipeline/export.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/error.h"
#include "io/bvh.h"
#include "io/file_util.h"

namespace motionfork::pipeline {
namespace {

// Sample k of the prediction as a motion; a non-finite value is named by sample, frame and joint.
Motion SampleMotion(const Prediction& p, const std::string& path, int k) {
  const int T = p.frames(), J = p.joints();
  const float* v = p.sample(k);
  for (size_t i = 0; i < static_cast<size_t>(T) * J * 3; ++i) {
    if (std::isfinite(v[i])) continue;
    const int t = static_cast<int>(i / (3 * J)), j = static_cast<int>(i / 3 % J);
    throw FormatError(FormatMessage(
        path,
        "sample " + std::to_string(k) + ", frame " + std::to_string(t) +
            (t < p.t_his ? " (history)" : " (future frame " + std::to_string(t - p.t_his) + ")"),
        "joint '" + p.skeleton->joint_name(j) + "' has a non-finite position (" +
            std::to_string(v[i]) + "); expected finite metres"));
  }
  return Motion(p.skeleton, p.fps, std::vector<float>(v, v + static_cast<size_t>(T) * J * 3));
}

}  // namespace

ExportedSample ExportSample(const Prediction& p, const std::string& source, int k,
                            const BvhWriteOptions& options) {
  const Motion m = SampleMotion(p, source, k);
  ExportedSample out;
  out.sample = k;
  try {
    out.text = BvhText(m, options);
  } catch (const std::invalid_argument& e) {
    throw FormatError(FormatMessage(source, "sample " + std::to_string(k), e.what()));
  }
  BvhOptions read_back;
  read_back.scale_to_metres = options.scale_to_metres;
  const Motion back = ReadBvhText(out.text, source, read_back);
  for (size_t i = 0; i < m.positions().size(); i += 3) {
    const float* a = &m.positions()[i];
    const float* b = &back.positions()[i];
    out.deviation = std::max(out.deviation, std::sqrt(std::pow(double(a[0]) - b[0], 2) +
                                                      std::pow(double(a[1]) - b[1], 2) +
                                                      std::pow(double(a[2]) - b[2], 2)));
  }
  return out;
}

std::string NumberedPath(const std::string& out, int k, int count) {
  const int digits = std::max<int>(2, static_cast<int>(std::to_string(count - 1).size()));
  char num[32];
  std::snprintf(num, sizeof(num), "_%0*d", digits, k);
  return out.substr(0, out.size() - 4) + num + out.substr(out.size() - 4);
}

std::vector<WrittenSample> ExportPrediction(const Prediction& p, const std::string& source,
                                            const std::string& out, int sample,
                                            const BvhWriteOptions& options) {
  if (sample >= p.k) {
    throw std::invalid_argument("--sample " + std::to_string(sample) + ": '" + source +
                                "' holds samples 0.." + std::to_string(p.k - 1));
  }
  std::vector<WrittenSample> written;
  for (int k = 0; k < p.k; ++k) {
    if (sample >= 0 && sample != k) continue;
    written.push_back(
        {ExportSample(p, source, k, options), sample >= 0 ? out : NumberedPath(out, k, p.k)});
  }
  for (const WrittenSample& w : written) WriteFileAtomically(w.path, w.sample.text);
  return written;
}

}  // namespace motionfork::pipeline
