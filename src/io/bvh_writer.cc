#include "io/bvh_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/file_util.h"

namespace motionfork {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadToDeg = 180.0 / kPi;
// Middle-angle cosine below which the first and last axes line up (gimbal lock).
constexpr double kGimbalCos = 1e-9;

// Axis indices (0 = X) of a rotation order such as "ZXY"; throws naming the bad value.
std::array<int, 3> ParseOrder(const std::string& order) {
  std::array<int, 3> axes{};
  bool seen[3] = {false, false, false};
  bool ok = order.size() == 3;
  for (size_t i = 0; ok && i < 3; ++i) {
    const char c = static_cast<char>(order[i] & ~0x20);  // upper case
    const int a = c == 'X' ? 0 : c == 'Y' ? 1 : c == 'Z' ? 2 : -1;
    ok = a >= 0 && !seen[a];
    if (ok) seen[a] = true;
    axes[i] = a;
  }
  if (!ok) {
    throw std::invalid_argument(
        "BvhWriteOptions::rotation_order: expected a permutation of XYZ "
        "(e.g. ZXY), got '" +
        order + "'");
  }
  return axes;
}

// Row-major rotation by `angle` radians about axis 0/1/2 (right-handed).
std::array<double, 9> AxisRotation(int axis, double angle) {
  std::array<double, 9> m{};
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  const double c = std::cos(angle), s = std::sin(angle);
  m[3 * axis + axis] = 1;
  m[3 * u + u] = c;
  m[3 * v + v] = c;
  m[3 * v + u] = s;
  m[3 * u + v] = -s;
  return m;
}

// a^T b for row-major 3x3 matrices.
std::array<double, 9> TransposeTimes(const double* a, const double* b) {
  std::array<double, 9> out{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      out[3 * r + c] = a[r] * b[c] + a[3 + r] * b[3 + c] + a[6 + r] * b[6 + c];
    }
  }
  return out;
}

std::array<double, 3> EulerForAxes(const double* m, const std::array<int, 3>& axes,
                                   const std::array<double, 3>& previous) {
  const int i = axes[0], j = axes[1], k = axes[2];
  const double s = j == (i + 1) % 3 ? 1.0 : -1.0;  // +1 for the cyclic orders XYZ, YZX, ZXY
  auto at = [m](int r, int c) { return m[3 * r + c]; };
  const double sin_b = std::clamp(s * at(i, k), -1.0, 1.0);
  const double cos_b = std::hypot(at(i, i), at(i, j));
  const double b0 = std::atan2(sin_b, cos_b);
  const double a0 =
      cos_b > kGimbalCos ? std::atan2(-s * at(j, k), at(k, k)) : previous[0] / kRadToDeg;
  std::array<double, 3> best{};
  double best_distance = INFINITY;
  // The two solutions: (a, b, c) and (a + pi, pi - b, c + pi); c from what a and b leave over,
  // so the angles compose to the rotation even at gimbal lock.
  for (int solution = 0; solution < 2; ++solution) {
    const double a = solution == 0 ? a0 : a0 + kPi;
    const double b = solution == 0 ? b0 : kPi - b0;
    const std::array<double, 9> ra = AxisRotation(i, a), rb = AxisRotation(j, b);
    const std::array<double, 9> rest =
        TransposeTimes(rb.data(), TransposeTimes(ra.data(), m).data());
    const int u = (k + 1) % 3, v = (k + 2) % 3;
    const double c = std::atan2(rest[3 * v + u], rest[3 * u + u]);
    std::array<double, 3> angles = {a * kRadToDeg, b * kRadToDeg, c * kRadToDeg};
    double distance = 0;
    for (int n = 0; n < 3; ++n) {
      angles[n] += 360.0 * std::round((previous[n] - angles[n]) / 360.0);
      distance += (angles[n] - previous[n]) * (angles[n] - previous[n]);
    }
    if (distance < best_distance) {
      best_distance = distance;
      best = angles;
    }
  }
  return best;
}

// A number with `decimals` digits after the point, trailing zeros and "-0" dropped.
void AppendNumber(double v, int decimals, std::string* out) {
  char buf[128];
  int n = std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  if (n < 0 || n >= static_cast<int>(sizeof(buf))) n = std::snprintf(buf, sizeof(buf), "%.17g", v);
  if (std::memchr(buf, '.', n)) {
    while (buf[n - 1] == '0') --n;
    if (buf[n - 1] == '.') --n;
  }
  if (n == 2 && buf[0] == '-' && buf[1] == '0') {
    buf[0] = '0';
    n = 1;
  }
  out->append(buf, n);
}

void CheckNames(const Skeleton& skel) {
  for (int j = 0; j < skel.num_joints(); ++j) {
    const std::string& name = skel.joint_name(j);
    const bool bad = name.empty() || std::any_of(name.begin(), name.end(), [](char c) {
                       return c == '{' || c == '}' || c == ' ' || c == '\t' || c == '\n' ||
                              c == '\r' || c == '\v' || c == '\f';
                     });
    if (bad) {
      throw std::invalid_argument("WriteBvh: joint " + std::to_string(j) + " '" + name +
                                  "': expected a BVH joint name (non-empty, no whitespace or "
                                  "braces); rename it in the skeleton");
    }
  }
}

}  // namespace

std::array<double, 3> EulerDegrees(const double* rotation, const std::string& order,
                                   const std::array<double, 3>& previous) {
  return EulerForAxes(rotation, ParseOrder(order), previous);
}

void ValidateBvhWriteOptions(const BvhWriteOptions& options) {
  ParseOrder(options.rotation_order);
  if (!(options.scale_to_metres > 0) || !std::isfinite(options.scale_to_metres)) {
    throw std::invalid_argument(
        "BvhWriteOptions::scale_to_metres: expected a finite number > 0 "
        "(0.01 for centimetres, 1 for metres), got " +
        std::to_string(options.scale_to_metres));
  }
  if (options.decimals < 1 || options.decimals > 15) {
    throw std::invalid_argument("BvhWriteOptions::decimals: expected 1..15, got " +
                                std::to_string(options.decimals));
  }
}

std::string BvhText(const Motion& motion, const BvhWriteOptions& options) {
  ValidateBvhWriteOptions(options);
  const std::array<int, 3> axes = ParseOrder(options.rotation_order);
  if (motion.num_joints() > 0) CheckNames(motion.skeleton());
  const PoseFit fit = FitPose(motion, options.fit);
  const Skeleton& skel = motion.skeleton();
  const int T = fit.num_frames, J = fit.num_joints, dec = options.decimals;
  const double unit = 1.0 / options.scale_to_metres;  // metres -> file units

  std::vector<std::vector<int>> children(J);
  for (int j = 1; j < J; ++j) children[skel.parent(j)].push_back(j);
  std::string rotation_channels;
  for (int a : axes) rotation_channels += std::string(" ") + "XYZ"[a] + "rotation";

  // Hierarchy, depth-first; `order` is the file's joint order (the motion lines follow it).
  std::string out = "HIERARCHY\n";
  std::vector<int> order;
  auto offset_line = [&](const std::string& indent, const double* v, double factor) {
    out += indent + "OFFSET";
    for (int a = 0; a < 3; ++a) {
      out += ' ';
      AppendNumber(v[a] * factor, dec, &out);
    }
    out += '\n';
  };
  auto write_joint = [&](auto&& self, int j, int depth) -> void {
    const std::string indent(2 * depth, ' ');
    order.push_back(j);
    out += indent + (j == 0 ? "ROOT " : "JOINT ") + skel.joint_name(j) + "\n" + indent + "{\n";
    offset_line(indent + "  ", &fit.offsets[3 * j], unit);
    out += indent + "  CHANNELS " + (fit.translated[j] ? "6 Xposition Yposition Zposition" : "3") +
           rotation_channels + "\n";
    for (int c : children[j]) self(self, c, depth + 1);
    if (children[j].empty()) {
      out += indent + "  End Site\n" + indent + "  {\n";
      offset_line(indent + "    ", &fit.offsets[3 * j], 0.5 * unit);
      out += indent + "  }\n";
    }
    out += indent + "}\n";
  };
  write_joint(write_joint, 0, 0);

  char frame_time[64];
  std::snprintf(frame_time, sizeof(frame_time), "%.10g", 1.0 / motion.fps());
  out += "MOTION\nFrames: " + std::to_string(T) + "\nFrame Time: " + frame_time + "\n";
  std::vector<std::array<double, 3>> previous(J, std::array<double, 3>{0, 0, 0});
  for (int t = 0; t < T; ++t) {
    bool first = true;
    auto value = [&](double v) {
      if (!first) out += ' ';
      first = false;
      AppendNumber(v, dec, &out);
    };
    for (int j : order) {
      if (fit.translated[j]) {
        for (int a = 0; a < 3; ++a) value(fit.translation(t, j)[a] * unit);
      }
      previous[j] = EulerForAxes(fit.rotation(t, j), axes, previous[j]);
      for (double angle : previous[j]) value(angle);
    }
    out += '\n';
  }
  return out;
}

void WriteBvh(const std::string& path, const Motion& motion, const BvhWriteOptions& options) {
  WriteFileAtomically(path, BvhText(motion, options));
}

}  // namespace motionfork
