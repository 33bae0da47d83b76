// motionfork export PREDICTION -o OUT.bvh: each predicted sample (history + its future) as a BVH
// file of joint rotations, for animation tools.
#include <string>

#include "app_common.h"
#include "commands.h"
#include "flags.h"
#include "io/bvh_writer.h"
#include "io/prediction_file.h"
#include "pipeline/export_on_rig.h"

namespace motionfork::app {
namespace {

struct ExportOptions {
  std::string prediction, out;
  int sample = -1;  // -1: every sample
  std::string lengths = "mean";
  std::string rig = "history";
  BvhWriteOptions bvh;
};

void RunExport(const ExportOptions& o, const GlobalOptions& global) {
  BvhWriteOptions bvh = o.bvh;
  bvh.fit.lengths = o.lengths == "exact" ? BoneLengths::kExact : BoneLengths::kMean;
  PrintText(pipeline::ExportSamples(ReadPrediction(o.prediction), o.prediction, o.out, o.sample,
                                    o.rig, bvh, ConfigDir(global.config_dir)));
}

}  // namespace

void AddExportCommand(CLI::App& app, GlobalOptions& global) {
  const auto [cmd, o] = AddSubcommand<ExportOptions>(
      &app, global, RunExport, "export",
      R"(Write predicted samples as BVH files of joint rotations (Blender, Maya, MotionBuilder).
Each file holds one sample: the history, then that future. Every sample by default
(OUT_00.bvh .. OUT_{K-1}.bvh), or one with --sample.
When the history was a BVH file (--rig history, the default), each file is on that file's own
rig: its joint names, hierarchy, rest offsets and channels, its unit, axes and frame rate; the
history's own frames first, then the future with the rotations of the joints the model predicts
solved and the others (fingers, toes, twist bones) held at their last history pose. Bones stay
rigid; the largest distance this leaves a joint from the prediction is printed per file.
Otherwise (--rig model, or a .npy/.csv history) the file is on the model's skeleton: the rest
pose is the sample's mean pose; bones keep their mean lengths (--lengths mean), so joints move by
as much as the prediction's bone lengths wobble; --lengths exact keeps every position by giving
stretching bones translation channels. Check a file in Blender with tools/blender_check_bvh.py.)");
  AddInputFile(cmd, "PREDICTION", &o->prediction,
               "Prediction written by 'motionfork predict' (.json or .npy)");
  AddOutOption(cmd, &o->out, "Output path ending in .bvh; written all-or-nothing");
  cmd->add_option("--rig", o->rig,
                  "The skeleton to write on: history (default: the history's own BVH rig when it "
                  "was a BVH, else the model's), model, or a BVH file (the history file, moved)");
  cmd->add_option("--sample", o->sample, "Only this sample (0-based), written to OUT itself")
      ->check(NonNegativeNumber);
  cmd->add_option("--lengths", o->lengths,
                  "mean: every bone keeps its mean length (rotations only, as animators expect; "
                  "default); exact: bones whose length varies get translation channels, so every "
                  "position is kept")
      ->check(CLI::IsMember({"mean", "exact"}));
  cmd->add_option(
         "--scale", o->bvh.scale_to_metres,
         "File length unit in metres (default 0.01: centimetres, as most BVH files; 1: metres)")
      ->check(PositiveNumber);
  cmd->add_option("--rotation-order", o->bvh.rotation_order,
                  "Axis order of every joint's rotation channels (default ZXY; e.g. ZYX, XYZ)");
}

}  // namespace motionfork::app
