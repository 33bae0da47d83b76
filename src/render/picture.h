// One entry point over the pictures of a prediction: a strip figure (PNG, SVG) or the HTML viewer,
// the kind chosen by the output file's extension, as `motionfork render` makes them.
#pragma once

#include <string>
#include <vector>

#include "io/prediction_file.h"
#include "render/scene.h"
#include "render/strip_figure.h"

namespace motionfork::render {

enum class PictureKind { kPng, kSvg, kHtml };

// From the extension of `path` (.png, .svg, .html or .htm, any case); throws std::invalid_argument
// naming the path and the extension found.
PictureKind PictureKindOf(const std::string& path);

// "HISTORY from frame S, K futures of MODEL, fixed: PARTS" for a prediction; the input file's name
// for a motion shown as a prediction (PredictionFromMotion).
std::string DefaultTitle(const Prediction& p, const std::string& input);

struct PictureOptions {
  std::vector<int> pick;  // samples drawn, in this order; empty = the first `samples`
  int samples = 0;        // 0 = 5 in a figure, every sample in the viewer
  StripOptions strip;     // the figure's options; its camera serves the viewer too
};

struct Picture {
  std::string bytes;        // the file's content
  std::string description;  // "1200 x 800 px, 5 samples, a pose every 5 frames", "50 samples, ..."
};

// strip.title is used as given (DefaultTitle for none).
Picture RenderPicture(const Scene& scene, const Prediction& p, PictureKind kind,
                      const PictureOptions& options);

}  // namespace motionfork::render
