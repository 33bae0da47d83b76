#include "render/html_viewer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "render/viewer_template.h"  // generated from viewer.html: kViewerTemplate

namespace motionfork::render {
namespace {

using nlohmann::json;

constexpr const char* kDataPlaceholder = "/*@MOTIONFORK_DATA@*/null";

std::string Hex(const Rgb& c) {
  char buf[8];
  auto byte = [](double v) { return static_cast<int>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); };
  std::snprintf(buf, sizeof(buf), "#%02x%02x%02x", byte(c.r), byte(c.g), byte(c.b));
  return buf;
}

json PaletteJson(const Palette& p) {
  return {{"history", {Hex(p.history_left), Hex(p.history_right), Hex(p.history_centre)}},
          {"future", {Hex(p.future_left), Hex(p.future_right), Hex(p.future_centre)}},
          {"fixed", {Hex(p.fixed_left), Hex(p.fixed_right), Hex(p.fixed_centre)}},
          {"background", Hex(p.background)},
          {"history_row", Hex(p.history_row)},
          {"invalid_row", Hex(p.invalid_row)},
          {"text", Hex(p.text)},
          {"valid_mark", Hex(p.valid_mark)},
          {"invalid_mark", Hex(p.invalid_mark)}};
}

}  // namespace

std::string RenderViewerHtml(const Scene& scene, const ViewerOptions& options) {
  ValidateCamera(options.camera);
  std::vector<int> shown = options.samples;
  if (shown.empty()) {
    for (int k = 0; k < scene.k; ++k) shown.push_back(k);
  }
  const Skeleton& s = *scene.skeleton;
  const int T = scene.frames(), J = scene.joints();
  json samples = json::array(), positions = json::array();
  for (int k : shown) {
    if (k < 0 || k >= scene.k) {
      throw std::invalid_argument("viewer options: sample " + std::to_string(k) + ": expected 0.." +
                                  std::to_string(scene.k - 1));
    }
    json entry = {{"index", k}};
    if (!scene.samples.empty()) {
      const SampleValidity& v = scene.samples[k];
      entry["valid"] = v.valid;
      entry["failed"] = v.Failed();  // "angle_ranges", "prior_nll", "history"
      entry["violating_frames"] = v.violating_frames;
      if (v.prior_nll && std::isfinite(*v.prior_nll)) entry["prior_nll"] = *v.prior_nll;
    }
    samples.push_back(entry);
    // Millimetres as integers keep the page small: [T * J * 3] in the body frame.
    std::vector<int> mm(static_cast<size_t>(T) * J * 3);
    const float* p = scene.pose(k, 0);
    for (size_t i = 0; i < mm.size(); ++i) mm[i] = static_cast<int>(std::lround(p[i] * 1000.0f));
    positions.push_back(std::move(mm));
  }
  std::vector<int> sides(J);
  for (int j = 0; j < J; ++j)
    sides[j] = scene.sides[j] == Side::kLeft ? 0 : scene.sides[j] == Side::kRight ? 1 : 2;
  json data = {
      {"title", options.title.empty() ? "motionfork prediction" : options.title},
      {"fps", scene.fps},
      {"t_his", scene.t_his},
      {"t_pred", scene.t_pred},
      {"frames", T},
      {"joints", J},
      {"names", s.joint_names()},
      {"parents", s.parents()},
      {"sides", sides},
      {"fixed", std::vector<int>(scene.fixed.begin(), scene.fixed.end())},
      {"drawn", std::vector<int>(scene.drawn.begin(), scene.drawn.end())},
      {"visible", std::vector<int>(scene.visible.begin(), scene.visible.end())},
      {"pelvis", scene.pelvis},
      {"head", scene.head},
      {"fixed_parts", scene.fixed_parts},
      {"camera",
       {{"azimuth", options.camera.azimuth_deg}, {"elevation", options.camera.elevation_deg}}},
      {"palette", PaletteJson(options.palette)},
      {"samples", samples},
      {"positions", positions}};
  // Inside <script>, "</script>" or "<!--" in a name or title would end or confuse the element:
  // '<' only occurs inside JSON strings, where \u003c means the same.
  std::string text;
  for (char c : data.dump()) {
    if (c == '<') {
      text += "\\u003c";
    } else {
      text += c;
    }
  }

  std::string page(kViewerTemplate);
  const size_t at = page.find(kDataPlaceholder);
  if (at == std::string::npos) throw std::logic_error("viewer.html has no data placeholder");
  page.replace(at, std::char_traits<char>::length(kDataPlaceholder), text);
  return page;
}

}  // namespace motionfork::render
