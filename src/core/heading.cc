#include "core/heading.h"

#include <cctype>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/skeleton.h"

namespace motionfork {

UpAxis ParseUp(const std::string& up) {
  std::string u;
  for (char ch : up) u.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(ch))));
  const bool minus = !u.empty() && u[0] == '-';
  const std::string axis = !u.empty() && (minus || u[0] == '+') ? u.substr(1) : u;
  if (axis != "x" && axis != "y" && axis != "z") {
    throw std::invalid_argument("up axis '" + up + "': expected auto, y, z, x, -y, -z or -x");
  }
  return {axis[0] - 'x', minus ? -1 : 1};
}

std::pair<int, int> GroundAxes(UpAxis up) {
  if (up.axis < 0 || up.axis > 2 || (up.sign != 1 && up.sign != -1)) {
    throw std::invalid_argument("up axis " + std::to_string(up.axis) + " sign " +
                                std::to_string(up.sign) + ", expected axis 0-2 and sign +1 or -1");
  }
  return {(up.axis + 1) % 3, (up.axis + 2) % 3};
}

std::optional<HeadingJoints> FindHeadingJoints(const Skeleton& skeleton) {
  const auto& pairs = skeleton.left_right_pairs();
  if (pairs.empty()) return std::nullopt;
  for (const auto& [l, r] : pairs) {
    if (skeleton.parent(l) == 0 && skeleton.parent(r) == 0) return HeadingJoints{l, r};
  }
  return HeadingJoints{pairs.front().first, pairs.front().second};
}

HeadingJoints HeadingNodes(const Skeleton& skeleton) {
  const std::optional<HeadingJoints> j = FindHeadingJoints(skeleton);
  if (!j) {
    throw std::invalid_argument("skeleton '" + skeleton.name() +
                                "' names no left/right joint pair to tell the body's heading by");
  }
  if (j->left == 0 || j->right == 0) {
    throw std::invalid_argument("skeleton '" + skeleton.name() +
                                "': its heading pair includes the root, expected two other joints");
  }
  return {j->left - 1, j->right - 1};
}

namespace {

constexpr double kMinLine = 1e-3;  // metres: shorter lines on the ground tell no heading

// The right-to-left line of a pose on the ground plane.
std::pair<double, double> GroundLine(const float* pose, HeadingJoints j, int a, int b) {
  const float* l = pose + 3 * j.left;
  const float* r = pose + 3 * j.right;
  return {static_cast<double>(l[a]) - r[a], static_cast<double>(l[b]) - r[b]};
}

}  // namespace

double HeadingAngle(const float* pose, HeadingJoints joints, UpAxis up) {
  const auto [a, b] = GroundAxes(up);
  const auto [x, y] = GroundLine(pose, joints, a, b);
  if (std::hypot(x, y) < kMinLine) return std::numeric_limits<double>::quiet_NaN();
  return std::atan2(y, x);
}

double WindowHeading(const float* poses, int frames, int joints, int at, HeadingJoints hj,
                     UpAxis up) {
  if (at < 0 || at >= frames) {
    throw std::invalid_argument("heading: frame " + std::to_string(at) + " outside 0-" +
                                std::to_string(frames - 1));
  }
  const double h = HeadingAngle(poses + static_cast<size_t>(at) * joints * 3, hj, up);
  if (!std::isnan(h)) return h;
  const auto [a, b] = GroundAxes(up);
  double x = 0, y = 0;
  for (int t = 0; t < frames; ++t) {
    const auto [dx, dy] = GroundLine(poses + static_cast<size_t>(t) * joints * 3, hj, a, b);
    x += dx;
    y += dy;
  }
  return std::hypot(x, y) < kMinLine ? 0.0 : std::atan2(y, x);
}

void RotateAboutUp(float* xyz, size_t points, double angle, UpAxis up) {
  const auto [a, b] = GroundAxes(up);
  const double c = std::cos(angle), s = std::sin(angle);
  for (size_t i = 0; i < points; ++i) {
    float* p = xyz + 3 * i;
    const double x = p[a], y = p[b];
    p[a] = static_cast<float>(c * x - s * y);
    p[b] = static_cast<float>(s * x + c * y);
  }
}

double TurnToBodyFrame(float* poses, int frames, int joints, int history, HeadingJoints hj,
                       UpAxis up) {
  const double turn = -WindowHeading(poses, history, joints, history - 1, hj, up);
  RotateAboutUp(poses, static_cast<size_t>(frames) * joints, turn, up);
  return turn;
}

}  // namespace motionfork
