// A self-contained HTML viewer: one file, the data inline as JSON, a canvas per panel and plain
// JavaScript, no network. It animates the history and the K futures side by side in a grid (or
// one sample large), with play/pause, a frame slider, sample selection, speed and view angle; the
// fixed part is dashed in muted colours, invalid samples are tinted. The page template is
// src/render/viewer.html, compiled into the library.
//
// URL hash options (e.g. viewer.html#play&sample=3): play (start playing), frame=N, sample=K,
// speed=X. While it runs the page keeps the current frame in the title and in
// <span id="frame" data-frame="N" data-ticks="frames advanced so far">.
#pragma once

#include <string>
#include <vector>

#include "render/scene.h"
#include "render/strip_figure.h"

namespace motionfork::render {

struct ViewerOptions {
  std::vector<int> samples;  // sample indices shown, in order; empty = all
  Camera camera;             // the initial view (the page has a slider for the azimuth)
  Palette palette;           // the strip figure's colours
  std::string title;         // page heading; "" = "motionfork prediction"
};

// The page's HTML. Throws std::invalid_argument on a sample index out of range or a bad camera.
std::string RenderViewerHtml(const Scene& scene, const ViewerOptions& options);

}  // namespace motionfork::render
