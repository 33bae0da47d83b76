// Strip figures (PNG decoded back through cairo, SVG checked for well-formedness), the HTML
// viewer's page, and the scene's up/facing detection, on synthetic predictions.
#include <cairo.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "io/archive.h"
#include "io/bvh.h"
#include "render/html_viewer.h"
#include "render/scene.h"
#include "render/strip_figure.h"
#include "test_support.h"

namespace motionfork::render {
namespace {

constexpr int kHis = 15, kPred = 30;

// K samples of the test humanoid (Y up, facing +Z): the history is the same walk for all, each
// future continues a differently seeded walk from where the history's pelvis ended.
Prediction MakePrediction(int k = 3, std::vector<std::string> fixed = {}) {
  Prediction p;
  p.k = k;
  p.t_his = kHis;
  p.t_pred = kPred;
  p.fps = 30;
  p.fixed_parts = std::move(fixed);
  const Motion history = testing::MakeWalkingMotion(kHis, 30.0, 1);
  p.skeleton = history.skeleton_ptr();
  const int J = history.num_joints();
  for (int s = 0; s < k; ++s) {
    p.positions.insert(p.positions.end(), history.positions().begin(), history.positions().end());
    const Motion future = testing::MakeWalkingMotion(kPred, 30.0, 100 + s);
    const float* end = history.at(kHis - 1, 0);
    for (int t = 0; t < kPred; ++t) {
      for (int j = 0; j < J; ++j) {
        for (int a = 0; a < 3; ++a)
          p.positions.push_back(future.at(t, j)[a] - future.at(0, 0)[a] + end[a]);
      }
    }
    SampleValidity v;
    v.valid = s != 1;
    v.violating_frames = s == 1 ? 4 : 0;
    p.samples.push_back(v);
  }
  return p;
}

// The same prediction with +Z up: (x, y, z) -> (x, -z, y) turns the +Y-up data about the x axis.
Prediction ZUp(Prediction p) {
  for (size_t i = 0; i < p.positions.size(); i += 3) {
    const float y = p.positions[i + 1], z = p.positions[i + 2];
    p.positions[i + 1] = -z;
    p.positions[i + 2] = y;
  }
  return p;
}

struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
using Surface = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;

struct ReadCursor {
  const std::string* bytes;
  size_t at = 0;
};
cairo_status_t ReadFromString(void* closure, unsigned char* data, unsigned int length) {
  auto* c = static_cast<ReadCursor*>(closure);
  if (c->at + length > c->bytes->size()) return CAIRO_STATUS_READ_ERROR;
  std::memcpy(data, c->bytes->data() + c->at, length);
  c->at += length;
  return CAIRO_STATUS_SUCCESS;
}

// A decoded PNG as 0xRRGGBB pixels.
struct Image {
  int width = 0, height = 0;
  std::vector<uint32_t> pixels;
  // Pixels of exactly this colour in rows first_row.. (the legend above the poses uses the same
  // colours: pass the layout's rows_top to count the poses only).
  size_t Count(const Rgb& c, int first_row = 0) const {
    const uint32_t want = (static_cast<uint32_t>(std::lround(c.r * 255)) << 16) |
                          (static_cast<uint32_t>(std::lround(c.g * 255)) << 8) |
                          static_cast<uint32_t>(std::lround(c.b * 255));
    return std::count(pixels.begin() + static_cast<size_t>(first_row) * width, pixels.end(), want);
  }
  // The same in the rectangle [x0, x1) x [y0, y1).
  size_t CountIn(const Rgb& c, int x0, int y0, int x1, int y1) const {
    size_t n = 0;
    for (int y = y0; y < y1; ++y) {
      Image row{x1 - x0, 1, {pixels.begin() + y * width + x0, pixels.begin() + y * width + x1}};
      n += row.Count(c);
    }
    return n;
  }
};

Image DecodePng(const std::string& bytes) {
  ReadCursor cursor{&bytes};
  Surface s(cairo_image_surface_create_from_png_stream(ReadFromString, &cursor));
  REQUIRE(cairo_surface_status(s.get()) == CAIRO_STATUS_SUCCESS);
  Image img;
  img.width = cairo_image_surface_get_width(s.get());
  img.height = cairo_image_surface_get_height(s.get());
  const int stride = cairo_image_surface_get_stride(s.get());
  const unsigned char* data = cairo_image_surface_get_data(s.get());
  for (int y = 0; y < img.height; ++y) {
    const auto* row = reinterpret_cast<const uint32_t*>(data + static_cast<size_t>(y) * stride);
    for (int x = 0; x < img.width; ++x) img.pixels.push_back(row[x] & 0xffffff);  // opaque: ARGB
  }
  return img;
}

std::string Png(const Prediction& p, const StripOptions& o = {}) {
  return RenderStrip(BuildScene(p), o, ImageFormat::kPng);
}

// Tags balance and nest (comments, declarations, processing instructions and self-closing tags
// skipped); returns "" when well-formed, else what is wrong.
std::string XmlProblem(const std::string& xml) {
  std::vector<std::string> open;
  size_t i = 0;
  while ((i = xml.find('<', i)) != std::string::npos) {
    if (xml.compare(i, 4, "<!--") == 0) {
      i = xml.find("-->", i);
      if (i == std::string::npos) return "unterminated comment";
      continue;
    }
    const size_t end = xml.find('>', i);
    if (end == std::string::npos) return "unterminated tag at byte " + std::to_string(i);
    const std::string tag = xml.substr(i + 1, end - i - 1);
    i = end + 1;
    if (tag.empty() || tag[0] == '?' || tag[0] == '!' || tag.back() == '/') continue;
    if (tag[0] == '/') {
      const std::string name = tag.substr(1, tag.find_first_of(" \t\n") - 1);
      if (open.empty() || open.back() != name)
        return "</" + name + "> does not close <" + (open.empty() ? "" : open.back()) + ">";
      open.pop_back();
    } else {
      open.push_back(tag.substr(0, tag.find_first_of(" \t\n")));
    }
  }
  return open.empty() ? "" : "<" + open.back() + "> never closed";
}

size_t Occurrences(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("strip PNG decodes with the layout's size and shows both sides' colours") {
  const Prediction p = MakePrediction();
  StripOptions o;
  o.row_height = 120;
  o.column_width = 50;
  o.every = 5;
  const StripLayout layout = LayoutStrip(BuildScene(p), o);
  // History frames 4 9 14, future frames 19..44: 9 columns; rows: history + 3 samples.
  CHECK(layout.history_frames == std::vector<int>{4, 9, 14});
  CHECK(layout.future_frames == std::vector<int>{19, 24, 29, 34, 39, 44});
  // Half a column of room on the right, then the ground-track squares (the row less its padding).
  CHECK(layout.width == 12 * 2 + 120 + 9 * 50 + 25 + 12 + (120 - 20));
  o.ground_track = false;
  CHECK(LayoutStrip(BuildScene(p), o).width == 12 * 2 + 120 + 9 * 50 + 25);
  o.ground_track = true;
  CHECK(layout.height == 12 * 2 + 22 + 18 + 4 * 120);

  const Image img = DecodePng(Png(p, o));
  CHECK(img.width == layout.width);
  CHECK(img.height == layout.height);
  const Palette palette;
  const size_t background = img.Count(palette.background);
  CHECK(background < img.pixels.size() * 97 / 100);  // not blank
  CHECK(std::set<uint32_t>(img.pixels.begin(), img.pixels.end()).size() > 50);
  // Interior pixels of 3 px bones carry the exact colours.
  const int poses = layout.rows_top;
  CHECK(img.Count(palette.future_left, poses) > 100);
  CHECK(img.Count(palette.future_right, poses) > 100);
  CHECK(img.Count(palette.history_left, poses) > 30);
  CHECK(img.Count(palette.history_right, poses) > 30);
  CHECK(img.Count(palette.fixed_left) == 0);            // nothing fixed
  CHECK(img.Count(palette.invalid_row, poses) > 1000);  // sample 1 is invalid
}

TEST_CASE("strip ground tracks show the pelvis walking on ahead of the body") {
  // The synthetic walk's root moves 1.2 m/s along the way the body faces: up the page, seen
  // from above.
  const Prediction p = MakePrediction(2);
  StripOptions o;
  o.row_height = 120;
  o.every = 5;
  const StripLayout layout = LayoutStrip(BuildScene(p), o);
  REQUIRE(layout.track_left > 0);
  const Image img = DecodePng(Png(p, o));
  const Palette palette;
  const int side = 120 - 20, top = layout.rows_top + 120 + 10;  // the first sample's row
  const int x0 = layout.track_left, x1 = x0 + side;
  const size_t ahead = img.CountIn(palette.future_centre, x0, top, x1, top + side / 2 - 3);
  const size_t behind = img.CountIn(palette.future_centre, x0, top + side / 2 + 3, x1, top + side);
  CHECK(ahead > 20);
  CHECK(behind == 0);
}

TEST_CASE("strip PNG draws a fixed part in its own style and only then") {
  const Palette palette;
  const Prediction with_legs_fixed = MakePrediction(2, {"legs"});
  const int poses = LayoutStrip(BuildScene(with_legs_fixed), {}).rows_top;
  const Image fixed = DecodePng(Png(with_legs_fixed));
  CHECK(fixed.Count(palette.fixed_left, poses) > 30);
  CHECK(fixed.Count(palette.fixed_right, poses) > 30);
  // Arms stay in the future colours.
  CHECK(fixed.Count(palette.future_left, poses) > 30);
  const Image free = DecodePng(Png(MakePrediction(2)));
  CHECK(free.Count(palette.fixed_left) == 0);
  CHECK(free.Count(palette.fixed_right) == 0);
  // All samples valid: no tinted row.
  Prediction valid = MakePrediction(1);
  CHECK(DecodePng(Png(valid)).Count(palette.invalid_row) == 0);
}

TEST_CASE("strip overlay puts all futures in one row") {
  const Scene scene = BuildScene(MakePrediction(4));
  StripOptions o;
  o.overlay = true;
  const StripLayout layout = LayoutStrip(scene, o);
  CHECK(layout.future_rows == 1);
  CHECK(layout.samples.size() == 4);
  const Image img = DecodePng(RenderStrip(scene, o, ImageFormat::kPng));
  CHECK(img.height == layout.height);
  CHECK(img.Count(Palette().background) < img.pixels.size());
}

TEST_CASE("strip SVG is well-formed and holds a path per bone") {
  StripOptions o;
  o.every = 10;
  o.title = "a <title> & \"quotes\"";
  const Scene scene = BuildScene(MakePrediction(2));
  const StripLayout layout = LayoutStrip(scene, o);
  const std::string svg = RenderStrip(scene, o, ImageFormat::kSvg);
  REQUIRE(svg.rfind("<?xml", 0) == 0);
  CHECK(svg.find("<svg") != std::string::npos);
  CHECK(XmlProblem(svg).empty());
  CHECK(svg.find("width=\"" + std::to_string(layout.width) + "pt\"") != std::string::npos);
  // 16 bones per pose; poses: the history row, then per sample the context pose and the futures.
  const size_t poses = layout.history_frames.size() + 2 * (1 + layout.future_frames.size());
  CHECK(Occurrences(svg, "<path") >= 16 * poses);
}

TEST_CASE("viewer HTML holds the data inline and no external URLs") {
  Prediction p = MakePrediction(3, {"legs"});
  ViewerOptions o;
  o.title = "walk </script><script>alert(1)</script>";
  const std::string html = RenderViewerHtml(BuildScene(p), o);
  CHECK(html.rfind("<!DOCTYPE html>", 0) == 0);
  CHECK(html.find("http://") == std::string::npos);
  CHECK(html.find("https://") == std::string::npos);
  CHECK(html.find("/*@MOTIONFORK_DATA@*/") == std::string::npos);
  // The title cannot end the script element: one opening and one closing script tag.
  CHECK(Occurrences(html, "<script") == 1);
  CHECK(Occurrences(html, "</script>") == 1);

  const std::string marker = "const DATA = ";
  const size_t begin = html.find(marker);
  REQUIRE(begin != std::string::npos);
  const size_t end = html.find(";\n", begin);
  const nlohmann::json data =
      nlohmann::json::parse(html.substr(begin + marker.size(), end - begin - marker.size()));
  CHECK(data["title"] == o.title);
  CHECK(data["frames"] == kHis + kPred);
  CHECK(data["t_his"] == kHis);
  CHECK(data["fixed_parts"] == std::vector<std::string>{"legs"});
  REQUIRE(data["positions"].size() == 3);
  CHECK(data["positions"][0].size() == static_cast<size_t>((kHis + kPred) * 17 * 3));
  CHECK(data["samples"][1]["valid"] == false);
  CHECK(data["fixed"][p.skeleton->Index("Foot_L")] == 1);
  CHECK(data["fixed"][p.skeleton->Index("Hand_L")] == 0);
  // Millimetres in the body frame: the last history pelvis is the origin.
  const Scene scene = BuildScene(p);
  CHECK(data["positions"][2][3 * 17 * 20 + 1].get<int>() ==
        std::lround(scene.pose(2, 20)[1] * 1000));

  o.samples = {2};
  const std::string one = RenderViewerHtml(scene, o);
  CHECK(Occurrences(one, "\"index\":2") == 1);
  o.samples = {3};
  CHECK_THROWS_WITH(RenderViewerHtml(scene, o),
                    Catch::Contains("sample 3") && Catch::Contains("0..2"));
}

TEST_CASE("scene finds the up axis and turns the body to face the viewer") {
  for (const bool z_up : {false, true}) {
    const Prediction p = z_up ? ZUp(MakePrediction()) : MakePrediction();
    const Scene scene = BuildScene(p);
    CHECK(scene.up.axis == (z_up ? 2 : 1));
    CHECK(scene.up.sign == 1);
    const Skeleton& s = *p.skeleton;
    CHECK(scene.head == s.Index("Head"));
    CHECK(scene.sides[s.Index("Hand_L")] == Side::kLeft);
    CHECK(scene.sides[s.Index("Hand_R")] == Side::kRight);
    CHECK(scene.sides[s.Index("Spine")] == Side::kCentre);
    const float* pose = scene.pose(0, kHis - 1);
    auto at = [&](const char* joint, int a) { return pose[3 * s.Index(joint) + a]; };
    CHECK(at("Hips", 0) == Approx(0).margin(1e-5));  // the anchor pelvis is the origin
    CHECK(at("Hips", 2) == Approx(0).margin(1e-5));
    CHECK(at("Head", 1) > at("Hips", 1) + 0.5f);       // up
    CHECK(at("UpperLeg_L", 0) > at("UpperLeg_R", 0));  // the body's left is +x
    CHECK(at("LowerLeg_L", 2) > at("Foot_L", 2));      // the knees bend to the viewer (+z)
  }
  // The option wins over the data.
  SceneOptions o;
  o.up = ParseSignedAxis("-x");
  CHECK(BuildScene(MakePrediction(), o).up.axis == 0);
  CHECK(ToString(ParseSignedAxis("Z")) == "+z");
  CHECK_THROWS_WITH(ParseSignedAxis("up"), Catch::Contains("'up'"));
}

TEST_CASE("scene ground is the lowest joint") {
  const Scene scene = BuildScene(MakePrediction());
  float lowest = 1e9f;
  for (size_t i = 1; i < scene.body.size(); i += 3) lowest = std::min(lowest, scene.body[i]);
  CHECK(lowest == Approx(0).margin(1e-6));
}

TEST_CASE("a plain motion is one strip without a history row") {
  const Prediction p = PredictionFromMotion(testing::MakeWalkingMotion(60));
  const Scene scene = BuildScene(p);
  StripOptions o;
  const StripLayout layout = LayoutStrip(scene, o);
  CHECK(layout.history_frames.empty());
  CHECK(layout.future_rows == 1);
  CHECK(layout.every == 5);  // about 12 poses
  CHECK(layout.future_frames.front() == 0);
  const Image img = DecodePng(RenderStrip(scene, o, ImageFormat::kPng));
  CHECK(img.Count(Palette().future_left, layout.rows_top) > 30);
  CHECK(img.Count(Palette().history_left) == 0);
}

TEST_CASE("bad predictions and options are rejected with what was expected") {
  Prediction p = MakePrediction();
  Prediction short_positions = p;
  short_positions.positions.pop_back();
  CHECK_THROWS_WITH(BuildScene(short_positions),
                    Catch::Contains("expected") && Catch::Contains("[3, 45, 17, 3]"));
  Prediction nan = p;
  nan.positions[(1 * 45 + 20) * 51 + 3 * 13 + 1] = std::nanf("");
  CHECK_THROWS_WITH(BuildScene(nan), Catch::Contains("sample 1, frame 20, joint 'Hand_L'"));
  Prediction unknown_part = p;
  unknown_part.fixed_parts = {"tail"};
  CHECK_THROWS_WITH(BuildScene(unknown_part),
                    Catch::Contains("'tail'") && Catch::Contains("legs, upper"));
  Prediction empty = p;
  empty.k = 0;
  empty.positions.clear();
  empty.samples.clear();
  CHECK_THROWS_WITH(BuildScene(empty), Catch::Contains("at least one sample"));

  const Scene scene = BuildScene(p);
  StripOptions o;
  o.samples = {0, 5};
  CHECK_THROWS_WITH(LayoutStrip(scene, o), Catch::Contains("sample 5") && Catch::Contains("0..2"));
  o = {};
  o.row_height = 10;
  CHECK_THROWS_WITH(LayoutStrip(scene, o),
                    Catch::Contains("row_height") && Catch::Contains("40..4000"));
  o = {};
  o.camera.elevation_deg = 95;
  CHECK_THROWS_WITH(LayoutStrip(scene, o), Catch::Contains("elevation_deg"));
  o = {};
  o.every = 1;
  o.column_width = 2000;
  CHECK_THROWS_WITH(LayoutStrip(scene, o), Catch::Contains("at most"));
}

TEST_CASE("a raw Bandai BVH clip stands upright and life-size and faces the viewer") {
  const std::string data = testing::SharedDataDir("data/bandai");
  if (data.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  std::string text;
  ForEachArchiveFile(
      data + "/bandai-1.tar.xz",
      [](const std::string& path) {
        return path.find("dataset-1_walk_normal_001.bvh") != std::string::npos;
      },
      [&](const std::string&, std::string_view bytes) { text = bytes; });
  REQUIRE(!text.empty());
  BvhOptions bvh;
  bvh.scale_to_metres = 0.01;
  const Motion clip = ReadBvhText(text, "dataset-1_walk_normal_001.bvh", bvh);
  // 22 joints, no left/right pairs: sides come from the names, the ground-level joint_Root is
  // not drawn and Hips is the pelvis.
  const Scene scene = BuildScene(PredictionFromMotion(clip));
  const Skeleton& s = clip.skeleton();
  CHECK(ToString(scene.up) == "+y");
  CHECK(scene.pelvis == s.Index("Hips"));
  CHECK(scene.head == s.Index("Head"));
  CHECK_FALSE(scene.drawn[s.Index("Hips")]);
  CHECK_FALSE(scene.visible[s.Index("joint_Root")]);  // it stays put while the body moves away
  CHECK(scene.sides[s.Index("Toes_L")] == Side::kLeft);
  CHECK(scene.sides[s.Index("Shoulder_R")] == Side::kRight);
  CHECK(scene.sides[s.Index("Neck")] == Side::kCentre);
  // Means over the first second (the frames the facing direction comes from).
  auto mean = [&](const char* joint, int a) {
    double sum = 0;
    for (int t = 0; t < 30; ++t) sum += scene.pose(0, t)[3 * s.Index(joint) + a];
    return static_cast<float>(sum / 30);
  };
  const float height = mean("Head", 1) - std::min(mean("Toes_L", 1), mean("Toes_R", 1));
  CHECK(height > 1.2f);  // a person, not squashed or in centimetres
  CHECK(height < 1.9f);
  const float shoulders = mean("UpperArm_L", 0) - mean("UpperArm_R", 0);
  CHECK(shoulders > 0.15f);  // the left side on +x, seen from the front on the viewer's right
  CHECK(shoulders < 0.6f);
  const float toes_l = mean("Toes_L", 2) - mean("Foot_L", 2),
              toes_r = mean("Toes_R", 2) - mean("Foot_R", 2);
  CHECK(toes_l > 0.02f);  // the feet point at the viewer
  CHECK(toes_r > 0.02f);
  WARN("Bandai walk: " << height << " m from toes to head joint, " << shoulders
                       << " m between the shoulders, toes " << toes_l << " and " << toes_r
                       << " m ahead of the ankles");

  const Image img = DecodePng(RenderStrip(scene, {}, ImageFormat::kPng));
  const int poses = LayoutStrip(scene, {}).rows_top;
  CHECK(img.Count(Palette().future_left, poses) > 100);
  CHECK(img.Count(Palette().future_right, poses) > 100);
}

}  // namespace motionfork::render
