// motionfork render INPUT -o FILE.png|.svg|.html: pictures of a prediction (or a motion file).
#include <cstdio>

#include "app_common.h"
#include "commands.h"
#include "flags.h"
#include "io/file_util.h"
#include "io/prediction_file.h"
#include "motion_options.h"
#include "render/picture.h"
#include "render/scene.h"

namespace motionfork::app {
namespace {

struct RenderOptions {
  std::string input;
  std::string out;
  int samples = 0;  // 0 = 5 in a figure, all in the viewer
  std::vector<int> pick;
  render::StripOptions
      strip;  // figure options straight from the flags (its camera serves the viewer too)
  MotionInputOptions input_options;
};

void RunRender(const RenderOptions& o, const GlobalOptions& g) {
  const render::PictureKind kind = render::PictureKindOf(o.out);
  Prediction p;
  if (IsPredictionPath(o.input)) {
    p = ReadPrediction(o.input);
  } else {
    p = render::PredictionFromMotion(
        pipeline::LoadMotionInput(o.input, WithConfigDir(o.input_options, ConfigDir(g.config_dir)))
            .motion);
  }
  if (p.k < 1) throw std::invalid_argument(o.input + ": expected at least one sample, got 0");
  render::SceneOptions scene_options;
  if (!o.input_options.up.empty() && o.input_options.up != "auto")
    scene_options.up = render::ParseSignedAxis(o.input_options.up);
  const render::Scene scene = render::BuildScene(p, scene_options);
  render::PictureOptions picture_options{o.pick, o.samples, o.strip};
  if (o.strip.title.empty()) picture_options.strip.title = render::DefaultTitle(p, o.input);
  const render::Picture picture = render::RenderPicture(scene, p, kind, picture_options);
  WriteFileAtomically(o.out, picture.bytes);
  std::printf("wrote %s (%s; up axis %s)\n", o.out.c_str(), picture.description.c_str(),
              render::ToString(scene.up).c_str());
}

}  // namespace

void AddRenderCommand(CLI::App& app, GlobalOptions& global) {
  const auto [cmd, o] = AddSubcommand<RenderOptions>(
      &app, global, RunRender, "render",
      R"(Pictures of a prediction (OUT.json/OUT.npy from 'motionfork predict') or of a motion file.
FILE.png / FILE.svg: a strip figure (a pose every few frames; the history row, then one row per
future; left limbs red, right blue, the history in pale tints, a fixed part dashed, invalid
samples tinted). FILE.html: a self-contained viewer (no network) animating the history and the
futures side by side, with play/pause, a frame slider, sample selection and speed.)");
  AddInputFile(cmd, "INPUT", &o->input,
               "A prediction (.json, or .npy with its .json beside it) or a motion file (.bvh, "
               ".npy, .csv)");
  AddOutOption(cmd, &o->out, "Output file: .png, .svg or .html");
  cmd->add_option("--count", o->samples,
                  "Samples shown: the first N (default 5 in a figure, all in the viewer)")
      ->check(CLI::Range(1, 1000000));
  AddDeprecatedOption(cmd, "--samples", "--count", &o->samples);
  cmd->add_option("--pick", o->pick,
                  "Samples shown, by index (e.g. --pick 0,3,7); overrides --count")
      ->delimiter(',')
      ->check(NonNegativeNumber);
  cmd->add_option("--every", o->strip.every,
                  "Figure: frames between drawn poses (default: about 12 future poses a row)")
      ->check(CLI::Range(1, 1000000));
  cmd->add_flag("--overlay", o->strip.overlay,
                "Figure: all futures overlaid in one row (translucent) instead of one row each");
  cmd->add_option("--row-height", o->strip.row_height, "Figure: px per row (default 150)")
      ->check(CLI::Range(40, 4000));
  cmd->add_option("--column-width", o->strip.column_width, "Figure: px between poses (default 70)")
      ->check(CLI::Range(10, 2000));
  cmd->add_option("--line-width", o->strip.line_width, "Figure: bone width in px (default 3)")
      ->check(CLI::Range(0.5, 50.0));
  cmd->add_option("--azimuth", o->strip.camera.azimuth_deg,
                  "View around the up axis, degrees: 0 = from the front, 90 = from the body's left "
                  "(default 30)");
  cmd->add_option("--elevation", o->strip.camera.elevation_deg,
                  "View from above the horizon, degrees (default 8)")
      ->check(CLI::Range(-89.0, 89.0));
  cmd->add_option("--title", o->strip.title,
                  "Title (default: the history file, start frame and model)");
  AddMotionInputOptions(cmd, &o->input_options);
}

}  // namespace motionfork::app
