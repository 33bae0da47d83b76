// motionfork export PREDICTION -o OUT.bvh: each predicted sample (history + its future) as a BVH
// file of joint rotations, for animation tools.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app_common.h"
#include "commands.h"
#include "core/error.h"
#include "io/bvh.h"
#include "io/bvh_writer.h"
#include "io/file_util.h"
#include "io/prediction_file.h"

namespace motionfork::app {
namespace {

struct ExportOptions {
  std::string prediction, out;
  int sample = -1;  // -1: every sample
  std::string lengths = "mean";
  BvhWriteOptions bvh;
};

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

// OUT.bvh -> OUT_07.bvh (digits: at least 2, enough for K - 1).
std::string NumberedPath(const std::string& out, int k, int count) {
  const int digits = std::max<int>(2, static_cast<int>(std::to_string(count - 1).size()));
  char num[32];
  std::snprintf(num, sizeof(num), "_%0*d", digits, k);
  return out.substr(0, out.size() - 4) + num + out.substr(out.size() - 4);
}

void RunExport(const ExportOptions& o) {
  std::string ext = o.out.size() >= 4 ? o.out.substr(o.out.size() - 4) : "";
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  if (ext != ".bvh") {
    throw std::invalid_argument("-o '" + o.out + "': expected a path ending in .bvh");
  }
  BvhWriteOptions bvh = o.bvh;
  bvh.fit.lengths = o.lengths == "exact" ? BoneLengths::kExact : BoneLengths::kMean;
  ValidateBvhWriteOptions(bvh);
  const Prediction p = ReadPrediction(o.prediction);
  if (o.sample >= p.k) {
    throw std::invalid_argument("--sample " + std::to_string(o.sample) + ": '" + o.prediction +
                                "' holds samples 0.." + std::to_string(p.k - 1));
  }
  std::vector<int> samples;
  for (int k = 0; k < p.k; ++k) {
    if (o.sample < 0 || o.sample == k) samples.push_back(k);
  }
  // Every file's text first, so bad input writes nothing.
  struct Output {
    int sample;
    std::string path, text;
    double deviation;  // metres, from the prediction to what the file holds
  };
  std::vector<Output> outputs;
  BvhOptions read_back;
  read_back.scale_to_metres = bvh.scale_to_metres;
  for (int k : samples) {
    const Motion m = SampleMotion(p, o.prediction, k);
    Output out{k, o.sample >= 0 ? o.out : NumberedPath(o.out, k, p.k), "", 0};
    try {
      out.text = BvhText(m, bvh);
    } catch (const std::invalid_argument& e) {
      throw FormatError(FormatMessage(o.prediction, "sample " + std::to_string(k), e.what()));
    }
    // What a BVH reader gets back: bone lengths fixed (--lengths mean) move joints a little.
    const Motion back = ReadBvhText(out.text, out.path, read_back);
    for (size_t i = 0; i < m.positions().size(); i += 3) {
      const float* a = &m.positions()[i];
      const float* b = &back.positions()[i];
      out.deviation = std::max(out.deviation, std::sqrt(std::pow(double(a[0]) - b[0], 2) +
                                                        std::pow(double(a[1]) - b[1], 2) +
                                                        std::pow(double(a[2]) - b[2], 2)));
    }
    outputs.push_back(std::move(out));
  }
  for (const Output& out : outputs) {
    WriteFileAtomically(out.path, out.text);
    std::printf(
        "wrote %s: sample %d, %d frames (%d history + %d future) at %.6g Hz, %d joints; "
        "largest joint displacement from the prediction %.3f mm\n",
        out.path.c_str(), out.sample, p.frames(), p.t_his, p.t_pred, p.fps, p.joints(),
        out.deviation * 1000);
  }
}

}  // namespace

void AddExportCommand(CLI::App& app, GlobalOptions& /*global*/) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Write predicted samples as BVH files of joint rotations (Blender, Maya, MotionBuilder).\n"
      "Each file holds one sample: the history, then that future. Every sample by default\n"
      "(OUT_00.bvh .. OUT_{K-1}.bvh), or one with --sample. The rest pose is the sample's mean\n"
      "pose; bones keep their mean lengths (--lengths mean), so joints move by as much as the\n"
      "prediction's bone lengths wobble (the figure printed per file); --lengths exact keeps "
      "every\n"
      "position by giving stretching bones translation channels. Check a file in Blender with\n"
      "tools/blender_check_bvh.py.");
  cmd->add_option("PREDICTION", o->prediction,
                  "Prediction written by 'motionfork predict' (.json or .npy)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", o->out, "Output path ending in .bvh; written all-or-nothing")
      ->required();
  cmd->add_option("--sample", o->sample, "Only this sample (0-based), written to OUT itself")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--lengths", o->lengths,
                  "mean: every bone keeps its mean length (rotations only, as animators expect; "
                  "default); exact: bones whose length varies get translation channels, so every "
                  "position is kept")
      ->check(CLI::IsMember({"mean", "exact"}));
  cmd->add_option(
         "--scale", o->bvh.scale_to_metres,
         "File length unit in metres (default 0.01: centimetres, as most BVH files; 1: metres)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--rotation-order", o->bvh.rotation_order,
                  "Axis order of every joint's rotation channels (default ZXY; e.g. ZYX, XYZ)");
  cmd->callback([o] { RunExport(*o); });
}

}  // namespace motionfork::app
