// Strip figures like the GSPS/DLow papers': poses every n-th frame along time, one row for the
// history and one row per future (or all futures overlaid in one row), drawn with cairo as PNG or
// SVG.
//
//   label  | history poses ........ |
//   column |          (last history) future poses ......... |   one row per sample
//
// Time runs left to right on one axis: each future row starts with the last history pose (in the
// history's colours) in the history's last column. Left and right limbs get two colours; the
// history is drawn in grey-ish tints of them; joints of a fixed part (Prediction::fixed_parts)
// are drawn dashed in muted tones; invalid samples get a tinted row and a red cross.
#pragma once

#include <string>
#include <vector>

#include "render/scene.h"

namespace motionfork::render {

struct Rgb {
  double r, g, b;  // 0..1
};
// 0xRRGGBB -> Rgb.
constexpr Rgb RgbFromHex(unsigned hex) {
  return {((hex >> 16) & 0xff) / 255.0, ((hex >> 8) & 0xff) / 255.0, (hex & 0xff) / 255.0};
}

// Bone colours by role and side. A bone takes the side of its child joint.
struct Palette {
  Rgb future_left = RgbFromHex(0xd62728), future_right = RgbFromHex(0x1f77b4),
      future_centre = RgbFromHex(0x333333);
  Rgb history_left = RgbFromHex(0xd8a7a7), history_right = RgbFromHex(0xa5bdd4),
      history_centre = RgbFromHex(0x9a9a9a);
  Rgb fixed_left = RgbFromHex(0xa66f6f), fixed_right = RgbFromHex(0x6a86a3),
      fixed_centre = RgbFromHex(0x7a7a7a);  // drawn dashed
  Rgb background = RgbFromHex(0xffffff), history_row = RgbFromHex(0xf3f3f3),
      invalid_row = RgbFromHex(0xfbe3e3), separator = RgbFromHex(0xdddddd),
      text = RgbFromHex(0x202020);
  Rgb valid_mark = RgbFromHex(0x2ca02c), invalid_mark = RgbFromHex(0xc00000);
};

struct StripOptions {
  std::vector<int> samples;    // sample indices drawn, in this order; empty = the first max_samples
  int max_samples = 5;         // when samples is empty (>= 1)
  int every = 0;               // frames between drawn poses (>= 1); 0 = about 12 future poses a row
  bool overlay = false;        // all futures in one row, translucent, instead of one row each
  double overlay_alpha = 0.4;  // (0, 1]
  int row_height = 150;        // px per row of poses (40..4000)
  int column_width = 70;       // px between neighbouring poses (10..2000)
  double line_width = 3;       // px (0.5..50)
  Camera camera;
  Palette palette;
  std::string title;  // drawn at the top; "" = none
  // A top-down square at the end of each future row: the ground track of the pelvis (the history
  // grey, the future in colour) over a half-metre grid, so that where the body goes shows (the
  // poses themselves are drawn centred on the pelvis).
  bool ground_track = true;
};

enum class ImageFormat { kPng, kSvg };

// Where everything goes; width and height are the image's, px.
struct StripLayout {
  int width = 0, height = 0;
  int rows_top = 0;                 // y of the first row of poses (above: title, legend, times)
  int every = 1;                    // resolved frame step
  std::vector<int> history_frames;  // frames in the history row (empty: no history row)
  std::vector<int> future_frames;   // frames in each future row
  std::vector<int> samples;         // samples drawn
  int future_rows = 0;              // 1 when overlaid, else samples.size()
  int track_left = 0;               // x of the ground-track squares; 0 = none
};

// Validates the options against the scene (the message names the field, its value and the rule)
// and lays the figure out.
StripLayout LayoutStrip(const Scene& scene, const StripOptions& options);

// The figure as the bytes of a PNG or SVG file. Throws std::invalid_argument on bad options and
// std::runtime_error when cairo fails.
std::string RenderStrip(const Scene& scene, const StripOptions& options, ImageFormat format);

}  // namespace motionfork::render
