#include "render/strip_figure.h"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

namespace motionfork::render {
namespace {

// The judges a sample fails, short for a label: "angles 3 fr., prior, history".
std::string FailedShort(const SampleValidity& v) {
  std::string text;
  for (const std::string& judge : v.Failed()) {
    text += text.empty() ? "" : ", ";
    if (judge == "angle_ranges") {
      text += "angles " + std::to_string(v.violating_frames) + " fr.";
    } else {
      text += judge == "prior_nll" ? "prior" : judge;
    }
  }
  return text;
}

// Fixed parts of the layout, px.
constexpr int kMargin = 12;
constexpr int kLabelWidth = 120;
constexpr int kTitleHeight = 24;
constexpr int kLegendHeight = 22;
constexpr int kAxisHeight = 18;
constexpr int kRowPad = 10;           // above the tallest pose and below the ground
constexpr int kMinWidth = 520;        // room for the legend
constexpr int kMaxSide = 32000;       // cairo image surfaces stop at 32767 px
constexpr double kHeadRadius = 0.09;  // metres
constexpr double kFontSize = 12;

struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextDeleter {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
};
using SurfacePtr = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;
using ContextPtr = std::unique_ptr<cairo_t, ContextDeleter>;

void CheckStatus(cairo_status_t status, const char* what) {
  if (status != CAIRO_STATUS_SUCCESS) {
    throw std::runtime_error(std::string("render: cairo failed to ") + what + ": " +
                             cairo_status_to_string(status));
  }
}

cairo_status_t AppendToString(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

void SetColour(cairo_t* cr, const Rgb& c, double alpha = 1) {
  cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

template <typename T>
void Require(bool ok, const char* field, T value, const std::string& rule) {
  if (!ok) {
    throw std::invalid_argument(std::string("strip options: ") + field + " = " +
                                std::to_string(value) + ": expected " + rule);
  }
}

std::string Format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, v);
  return buf;
}

enum class Role { kHistory, kFuture };

class StripPainter {
 public:
  StripPainter(cairo_t* cr, const Scene& scene, const StripOptions& o, const StripLayout& layout)
      : cr_(cr), scene_(scene), o_(o), layout_(layout) {
    has_history_row_ = !layout.history_frames.empty();
    first_future_column_ = static_cast<int>(layout.history_frames.size());
    dots_ = std::none_of(scene.drawn.begin(), scene.drawn.end(), [](char d) { return d != 0; });
    FitScale();
    FitTrack();
  }

  void Paint() {
    SetColour(cr_, o_.palette.background);
    cairo_paint(cr_);
    cairo_select_font_face(cr_, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_line_cap(cr_, CAIRO_LINE_CAP_ROUND);
    cairo_set_line_join(cr_, CAIRO_LINE_JOIN_ROUND);
    PaintHeader();
    int row = 0;
    if (has_history_row_) {
      PaintRowBackground(row, o_.palette.history_row);
      const double hist_s = scene_.t_his / scene_.fps;
      PaintLabel(row, "history", Format("%.2f s", hist_s), nullptr);
      for (size_t c = 0; c < layout_.history_frames.size(); ++c) {
        DrawPose(scene_.pose(layout_.samples.front(), layout_.history_frames[c]), Role::kHistory,
                 static_cast<int>(c), row, 1.0);
      }
      ++row;
    }
    if (o_.overlay) {
      PaintOverlayRow(row);
    } else {
      for (int k : layout_.samples) PaintSampleRow(row++, k);
    }
  }

 private:
  double ColumnCentre(int c) const { return kMargin + kLabelWidth + (c + 0.5) * o_.column_width; }
  double RowTop(int row) const { return layout_.rows_top + row * o_.row_height; }
  double Baseline(int row) const { return RowTop(row) + o_.row_height - kRowPad; }

  // One scale for every pose: the tallest drawn pose fills a row.
  void FitScale() {
    std::vector<ScreenPoint> pts;
    bool first = true;
    auto visit = [&](int k, int t) {
      ProjectCentred(scene_.pose(k, t), &pts);
      for (int j = 0; j < scene_.joints(); ++j) {
        if (!scene_.visible[j]) continue;
        if (first || pts[j].y < ground_) ground_ = pts[j].y;
        if (first || pts[j].y > top_) top_ = pts[j].y;
        first = false;
      }
    };
    for (int t : layout_.history_frames) visit(layout_.samples.front(), t);
    for (int k : layout_.samples) {
      for (int t : layout_.future_frames) visit(k, t);
      if (scene_.t_his > 0) visit(k, scene_.t_his - 1);
    }
    const double head = scene_.head >= 0 ? kHeadRadius : 0;  // the circle reaches above the joint
    const double height_m = std::max(0.1, top_ + head - ground_);
    scale_ = (o_.row_height - 2.0 * kRowPad) / height_m;
  }

  // The ground tracks' scale: every drawn sample's pelvis over all frames fits its square, which
  // spans at least 1 m.
  void FitTrack() {
    track_reach_ = 0.5;
    for (int k : layout_.samples) {
      for (int t = 0; t < scene_.frames(); ++t) {
        const float* p = scene_.pose(k, t) + 3 * scene_.pelvis;
        track_reach_ = std::max({track_reach_, std::abs(double(p[0])), std::abs(double(p[2]))});
      }
    }
    track_reach_ *= 1.1;
  }

  // Row `row`'s top-down square: a grid, the history's track grey, each sample's future track.
  void PaintTrack(int row, const std::vector<int>& samples, double alpha) {
    if (layout_.track_left == 0) return;
    const double side = o_.row_height - 2.0 * kRowPad;
    const double x0 = layout_.track_left, y0 = RowTop(row) + kRowPad, half = side / 2;
    const double s = half / track_reach_;
    // Seen from above with the body facing up the page at the last history frame: its left is
    // the page's left.
    auto X = [&](const float* p) { return x0 + half - s * p[0]; };
    auto Y = [&](const float* p) { return y0 + half - s * p[2]; };
    SetColour(cr_, o_.palette.background);
    cairo_rectangle(cr_, x0, y0, side, side);
    cairo_fill(cr_);
    for (double g = -std::floor(track_reach_ / 0.5) * 0.5; g <= track_reach_; g += 0.5) {
      Line(x0 + half + s * g, y0, x0 + half + s * g, y0 + side, o_.palette.separator, false, 1, 1);
      Line(x0, y0 + half + s * g, x0 + side, y0 + half + s * g, o_.palette.separator, false, 1, 1);
    }
    auto path = [&](int k, int from, int to, const Rgb& c, double a) {
      SetColour(cr_, c, a);
      cairo_set_line_width(cr_, 2);
      for (int t = from; t <= to; ++t) {
        const float* p = scene_.pose(k, t) + 3 * scene_.pelvis;
        (t == from ? cairo_move_to : cairo_line_to)(cr_, X(p), Y(p));
      }
      cairo_stroke(cr_);
    };
    const int last = std::max(0, scene_.t_his - 1);
    if (scene_.t_his > 1) path(samples.front(), 0, last, o_.palette.history_centre, 1);
    for (int k : samples) path(k, last, scene_.frames() - 1, o_.palette.future_centre, alpha);
    const float* origin = scene_.pose(samples.front(), last) + 3 * scene_.pelvis;
    SetColour(cr_, o_.palette.text);
    cairo_arc(cr_, X(origin), Y(origin), 2.5, 0, 2 * M_PI);
    cairo_fill(cr_);
  }

  // Poses stand where they are vertically but are centred on the pelvis horizontally.
  void ProjectCentred(const float* pose, std::vector<ScreenPoint>* out) {
    const int J = scene_.joints();
    centred_.assign(pose, pose + 3 * J);
    const float px = pose[3 * scene_.pelvis], pz = pose[3 * scene_.pelvis + 2];
    for (int j = 0; j < J; ++j) {
      centred_[3 * j] -= px;
      centred_[3 * j + 2] -= pz;
    }
    Project(centred_.data(), J, o_.camera, out);
  }

  void Text(double x, double y, const std::string& s, double size = kFontSize, bool bold = false) {
    cairo_select_font_face(cr_, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr_, size);
    cairo_move_to(cr_, x, y);
    cairo_show_text(cr_, s.c_str());
  }
  double TextWidth(const std::string& s) {
    cairo_text_extents_t e;
    cairo_text_extents(cr_, s.c_str(), &e);
    return e.x_advance;
  }

  void Line(double x0, double y0, double x1, double y1, const Rgb& c, bool dashed, double alpha = 1,
            double width = 0) {
    SetColour(cr_, c, alpha);
    cairo_set_line_width(cr_, width > 0 ? width : o_.line_width);
    const double dash[] = {2.2 * o_.line_width, 1.8 * o_.line_width};
    cairo_set_dash(cr_, dash, dashed ? 2 : 0, 0);
    cairo_move_to(cr_, x0, y0);
    cairo_line_to(cr_, x1, y1);
    cairo_stroke(cr_);
    cairo_set_dash(cr_, nullptr, 0, 0);
  }

  // A legend entry: a short line in each colour, then the text; returns the next x.
  double LegendItem(double x, double y, std::initializer_list<Rgb> colours, bool dashed,
                    const std::string& text) {
    for (const Rgb& c : colours) {
      Line(x, y - 4, x + 18, y - 4, c, dashed, 1, 3);
      x += 24;
    }
    SetColour(cr_, o_.palette.text);
    Text(x, y, text);
    return x + TextWidth(text) + 16;
  }

  void PaintHeader() {
    double y = kMargin;
    if (!o_.title.empty()) {
      SetColour(cr_, o_.palette.text);
      Text(kMargin, y + 15, o_.title, 14, true);
      y += kTitleHeight;
    }
    const Palette& p = o_.palette;
    double x = kMargin;
    const double ly = y + 14;
    if (has_history_row_)
      x = LegendItem(x, ly, {p.history_left, p.history_right}, false, "history");
    const auto sided = [&](Side side) {
      return std::find(scene_.sides.begin(), scene_.sides.end(), side) != scene_.sides.end();
    };
    if (sided(Side::kLeft)) x = LegendItem(x, ly, {p.future_left}, false, "left");
    if (sided(Side::kRight)) x = LegendItem(x, ly, {p.future_right}, false, "right");
    if (!scene_.fixed_parts.empty()) {
      std::string parts;
      for (const std::string& s : scene_.fixed_parts) parts += (parts.empty() ? "" : ", ") + s;
      x = LegendItem(x, ly, {p.fixed_left, p.fixed_right}, true, "fixed: " + parts);
    }
    // Time of each column: seconds from the last history frame (a plain motion: from its start).
    SetColour(cr_, o_.palette.text, 0.7);
    const double ay = y + kLegendHeight + 12;
    double last_end = -1e9;
    auto label = [&](int c, int frame) {
      const int ref = scene_.t_his > 0 ? scene_.t_his - 1 : 0;
      const double s = (frame - ref) / scene_.fps;
      const std::string t =
          std::abs(s) < 1e-9 ? "0 s" : Format(scene_.t_his > 0 ? "%+.2f s" : "%.2f s", s);
      cairo_set_font_size(cr_, 10);
      const double w = TextWidth(t), x0 = ColumnCentre(c) - w / 2;
      if (x0 < last_end + 4) return;
      Text(x0, ay, t, 10);
      last_end = x0 + w;
    };
    for (size_t c = 0; c < layout_.history_frames.size(); ++c)
      label(static_cast<int>(c), layout_.history_frames[c]);
    for (size_t c = 0; c < layout_.future_frames.size(); ++c) {
      label(first_future_column_ + static_cast<int>(c), layout_.future_frames[c]);
    }
  }

  void PaintRowBackground(int row, const Rgb& colour) {
    SetColour(cr_, colour);
    cairo_rectangle(cr_, kMargin, RowTop(row), layout_.width - 2 * kMargin, o_.row_height);
    cairo_fill(cr_);
  }

  // Row label: a bold first line, a second line with an optional validity mark before it.
  void PaintLabel(int row, const std::string& first, const std::string& second, const bool* valid) {
    const double y = RowTop(row) + o_.row_height / 2.0;
    SetColour(cr_, o_.palette.text);
    Text(kMargin + 6, y - 4, first, kFontSize, true);
    double x = kMargin + 6;
    if (valid) {
      const Rgb& c = *valid ? o_.palette.valid_mark : o_.palette.invalid_mark;
      const double my = y + 10;
      if (*valid) {
        Line(x, my, x + 4, my + 4, c, false, 1, 2.5);
        Line(x + 4, my + 4, x + 11, my - 5, c, false, 1, 2.5);
      } else {
        Line(x, my - 5, x + 9, my + 4, c, false, 1, 2.5);
        Line(x, my + 4, x + 9, my - 5, c, false, 1, 2.5);
      }
      x += 16;
      SetColour(cr_, c);
    } else {
      SetColour(cr_, o_.palette.text);
    }
    Text(x, y + 14, second, 11);
  }

  void PaintSampleRow(int row, int k) {
    const bool known = !scene_.samples.empty();
    const SampleValidity v = known ? scene_.samples[k] : SampleValidity{};
    if (known && !v.valid) PaintRowBackground(row, o_.palette.invalid_row);
    if (row > 0)
      Line(kMargin, RowTop(row), layout_.width - kMargin, RowTop(row), o_.palette.separator, false,
           1, 1);
    std::string second;
    if (known) {
      second = v.valid ? "valid" : "invalid: " + FailedShort(v);
      if (v.prior_nll) second += Format(", NLL %.1f", *v.prior_nll);
    } else if (scene_.t_his == 0) {
      second = Format("%.2f s", scene_.t_pred / scene_.fps);
    }
    const bool valid = v.valid;
    PaintLabel(row, scene_.t_his == 0 && scene_.k == 1 ? "motion" : "sample " + std::to_string(k),
               second, known ? &valid : nullptr);
    if (scene_.t_his > 0)
      DrawPose(scene_.pose(k, scene_.t_his - 1), Role::kHistory, first_future_column_ - 1, row, 1);
    for (size_t c = 0; c < layout_.future_frames.size(); ++c) {
      DrawPose(scene_.pose(k, layout_.future_frames[c]), Role::kFuture,
               first_future_column_ + static_cast<int>(c), row, 1);
    }
    PaintTrack(row, {k}, 1);
  }

  void PaintOverlayRow(int row) {
    std::string invalid;
    for (int k : layout_.samples) {
      if (!scene_.samples.empty() && !scene_.samples[k].valid)
        invalid += (invalid.empty() ? "" : ", ") + std::to_string(k);
    }
    const bool valid = invalid.empty(), known = !scene_.samples.empty();
    PaintLabel(row, std::to_string(layout_.samples.size()) + " futures",
               !known  ? ""
               : valid ? "all valid"
                       : "invalid: " + invalid,
               known ? &valid : nullptr);
    const int k0 = layout_.samples.front();
    if (scene_.t_his > 0)
      DrawPose(scene_.pose(k0, scene_.t_his - 1), Role::kHistory, first_future_column_ - 1, row, 1);
    for (size_t c = 0; c < layout_.future_frames.size(); ++c) {
      for (int k : layout_.samples) {
        DrawPose(scene_.pose(k, layout_.future_frames[c]), Role::kFuture,
                 first_future_column_ + static_cast<int>(c), row, o_.overlay_alpha);
      }
    }
    PaintTrack(row, layout_.samples, o_.overlay_alpha);
  }

  const Rgb& BoneColour(int j, Role role) const {
    const Palette& p = o_.palette;
    const Side side = scene_.sides[j];
    if (role == Role::kHistory) {
      return side == Side::kLeft    ? p.history_left
             : side == Side::kRight ? p.history_right
                                    : p.history_centre;
    }
    if (scene_.fixed[j])
      return side == Side::kLeft    ? p.fixed_left
             : side == Side::kRight ? p.fixed_right
                                    : p.fixed_centre;
    return side == Side::kLeft    ? p.future_left
           : side == Side::kRight ? p.future_right
                                  : p.future_centre;
  }

  // Bones far to near (painter's order), the head circle among them at the head's depth.
  void DrawPose(const float* pose, Role role, int column, int row, double alpha) {
    const int J = scene_.joints();
    ProjectCentred(pose, &pts_);
    const double cx = ColumnCentre(column), base = Baseline(row);
    auto X = [&](int j) { return cx + scale_ * pts_[j].x; };
    auto Y = [&](int j) { return base - scale_ * (pts_[j].y - ground_); };
    order_.clear();
    for (int j = 0; j < J; ++j) {
      if (scene_.drawn[j])
        order_.push_back({0.5f * (pts_[j].depth + pts_[scene_.skeleton->parent(j)].depth), j});
    }
    if (scene_.head >= 0) order_.push_back({pts_[scene_.head].depth, -1});
    std::stable_sort(order_.begin(), order_.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    const bool dashed_role = role == Role::kFuture;
    for (const auto& [depth, j] : order_) {
      if (j >= 0) {
        const int par = scene_.skeleton->parent(j);
        Line(X(par), Y(par), X(j), Y(j), BoneColour(j, role), dashed_role && scene_.fixed[j],
             alpha);
        continue;
      }
      const int h = scene_.head;
      cairo_new_sub_path(cr_);
      cairo_arc(cr_, X(h), Y(h), kHeadRadius * scale_, 0, 2 * M_PI);
      if (alpha >= 1) {
        SetColour(cr_, o_.palette.background);
        cairo_fill_preserve(cr_);
      }
      SetColour(cr_, BoneColour(h, role), alpha);
      cairo_set_line_width(cr_, o_.line_width * 0.8);
      cairo_stroke(cr_);
    }
    if (dots_) {  // no limbs known: the joints as dots
      for (int j = 0; j < J; ++j) {
        cairo_new_sub_path(cr_);
        cairo_arc(cr_, X(j), Y(j), o_.line_width, 0, 2 * M_PI);
        SetColour(cr_, BoneColour(j, role), alpha);
        cairo_fill(cr_);
      }
    }
  }

  cairo_t* cr_;
  const Scene& scene_;
  const StripOptions& o_;
  const StripLayout& layout_;
  bool has_history_row_ = false;
  int first_future_column_ = 0;
  bool dots_ = false;           // no bone is drawn: joints as dots
  float ground_ = 0, top_ = 0;  // projected y range of the drawn poses, metres
  double track_reach_ = 1;      // metres from the origin to a ground-track square's edge
  double scale_ = 1;            // px per metre
  std::vector<ScreenPoint> pts_;
  std::vector<float> centred_;  // [J, 3]
  std::vector<std::pair<float, int>> order_;
};

}  // namespace

StripLayout LayoutStrip(const Scene& scene, const StripOptions& o) {
  Require(o.max_samples >= 1, "max_samples", o.max_samples, ">= 1");
  Require(o.every >= 0, "every", o.every, ">= 1 frames (0 = automatic)");
  Require(o.overlay_alpha > 0 && o.overlay_alpha <= 1, "overlay_alpha", o.overlay_alpha, "(0, 1]");
  Require(o.row_height >= 40 && o.row_height <= 4000, "row_height", o.row_height, "40..4000 px");
  Require(o.column_width >= 10 && o.column_width <= 2000, "column_width", o.column_width,
          "10..2000 px");
  Require(o.line_width >= 0.5 && o.line_width <= 50, "line_width", o.line_width, "0.5..50 px");
  ValidateCamera(o.camera);
  if (scene.k < 1) throw std::invalid_argument("strip: expected at least one sample, got 0");

  StripLayout l;
  l.samples = o.samples;
  if (l.samples.empty()) {
    for (int k = 0; k < std::min(o.max_samples, scene.k); ++k) l.samples.push_back(k);
  }
  for (int k : l.samples) {
    if (k < 0 || k >= scene.k) {
      throw std::invalid_argument("strip options: sample " + std::to_string(k) + ": expected 0.." +
                                  std::to_string(scene.k - 1) + " (the prediction has " +
                                  std::to_string(scene.k) + " samples)");
    }
  }
  const int T = scene.frames();
  l.every = o.every > 0 ? o.every : std::max(1, (std::max(scene.t_pred, scene.t_his) + 11) / 12);
  for (int t = scene.t_his - 1; t >= 0; t -= l.every)
    l.history_frames.insert(l.history_frames.begin(), t);
  const int first = scene.t_his > 0 ? scene.t_his - 1 + l.every : 0;
  if (scene.t_pred > 0) {
    for (int t = first; t < T; t += l.every) l.future_frames.push_back(t);
  }
  l.future_rows = l.future_frames.empty() ? 0 : o.overlay ? 1 : static_cast<int>(l.samples.size());
  const long columns = static_cast<long>(l.history_frames.size() + l.future_frames.size());
  const long rows = (l.history_frames.empty() ? 0 : 1) + l.future_rows;
  // Half a column more on the right: the last poses' arms reach past their column; then the
  // ground-track squares.
  const long poses_right = kMargin + kLabelWidth + (2 * columns + 1) * o.column_width / 2;
  const bool track = o.ground_track && l.future_rows > 0 && scene.t_his > 0;
  const long track_side = o.row_height - 2L * kRowPad;
  if (track) l.track_left = static_cast<int>(poses_right + kMargin);
  const long width =
      std::max<long>(kMinWidth, (track ? l.track_left + track_side : poses_right) + kMargin);
  l.rows_top = kMargin + (o.title.empty() ? 0 : kTitleHeight) + kLegendHeight + kAxisHeight;
  const long height = l.rows_top + rows * o.row_height + kMargin;
  if (width > kMaxSide || height > kMaxSide) {
    throw std::invalid_argument(
        "strip: the figure would be " + std::to_string(width) + " x " + std::to_string(height) +
        " px, expected at most " + std::to_string(kMaxSide) +
        " px a side: draw fewer samples, a larger frame step or smaller cells");
  }
  l.width = static_cast<int>(width);
  l.height = static_cast<int>(height);
  return l;
}

std::string RenderStrip(const Scene& scene, const StripOptions& options, ImageFormat format) {
  const StripLayout layout = LayoutStrip(scene, options);
  std::string bytes;
  SurfacePtr surface(
      format == ImageFormat::kPng
          ? cairo_image_surface_create(CAIRO_FORMAT_ARGB32, layout.width, layout.height)
          : cairo_svg_surface_create_for_stream(AppendToString, &bytes, layout.width,
                                                layout.height));
  CheckStatus(cairo_surface_status(surface.get()), "create a surface");
  {
    ContextPtr cr(cairo_create(surface.get()));
    StripPainter(cr.get(), scene, options, layout).Paint();
    CheckStatus(cairo_status(cr.get()), "draw the figure");
  }
  if (format == ImageFormat::kPng) {
    CheckStatus(cairo_surface_write_to_png_stream(surface.get(), AppendToString, &bytes),
                "encode the PNG");
  } else {
    cairo_surface_finish(surface.get());
    CheckStatus(cairo_surface_status(surface.get()), "write the SVG");
  }
  return bytes;
}

}  // namespace motionfork::render
