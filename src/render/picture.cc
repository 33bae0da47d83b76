#include "render/picture.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

#include "render/html_viewer.h"

namespace motionfork::render {

namespace fs = std::filesystem;

PictureKind PictureKindOf(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".png") return PictureKind::kPng;
  if (ext == ".svg") return PictureKind::kSvg;
  if (ext == ".html" || ext == ".htm") return PictureKind::kHtml;
  throw std::invalid_argument("-o " + path +
                              ": expected a file name ending in .png, .svg or .html, got '" +
                              (ext.empty() ? std::string("no extension") : ext) + "'");
}

std::string DefaultTitle(const Prediction& p, const std::string& input) {
  if (p.model.empty() && p.history.empty()) return fs::path(input).filename().string();
  std::string t = fs::path(p.history).filename().string() + " from frame " +
                  std::to_string(p.start_frame) + ", " + std::to_string(p.k) + " futures";
  if (!p.model.empty()) t += " of " + fs::path(p.model).filename().string();
  if (!p.fixed_parts.empty()) {
    t += ", fixed:";
    for (const std::string& part : p.fixed_parts) t += " " + part;
  }
  return t;
}

Picture RenderPicture(const Scene& scene, const Prediction& p, PictureKind kind,
                      const PictureOptions& o) {
  Picture picture;
  if (kind == PictureKind::kHtml) {
    ViewerOptions v;
    v.samples = o.pick;
    for (int k = 0; v.samples.empty() && o.samples > 0 && k < std::min(o.samples, p.k); ++k)
      v.samples.push_back(k);
    v.camera = o.strip.camera;
    v.title = o.strip.title;
    picture.bytes = RenderViewerHtml(scene, v);
    picture.description =
        std::to_string(v.samples.empty() ? p.k : static_cast<int>(v.samples.size())) +
        " samples, " + std::to_string(p.frames()) + " frames";
    return picture;
  }
  StripOptions s = o.strip;
  s.samples = o.pick;
  if (o.samples > 0) s.max_samples = o.samples;
  const StripLayout layout = LayoutStrip(scene, s);
  picture.bytes =
      RenderStrip(scene, s, kind == PictureKind::kPng ? ImageFormat::kPng : ImageFormat::kSvg);
  picture.description = std::to_string(layout.width) + " x " + std::to_string(layout.height) +
                        " px, " + std::to_string(layout.samples.size()) +
                        " samples, a pose every " + std::to_string(layout.every) + " frames";
  return picture;
}

}  // namespace motionfork::render
