#include "rig/body_frame.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "core/heading.h"

namespace motionfork {
namespace {

using Vec = std::array<double, 3>;

struct Unit {
  double metres;
  const char* name;
  const char* flag;
};
// In order of preference where two would fit.
constexpr Unit kUnits[] = {{1.0, "metres", "m"},
                           {0.01, "centimetres", "cm"},
                           {0.001, "millimetres", "mm"},
                           {0.0254, "inches", "in"}};
// Leg (hip-knee-ankle) + trunk (pelvis-spine-chest-neck-head) of people from children to tall
// adults, metres: 1.32 for the Bandai actors, about 1.6 for Human3.6M's subjects.
constexpr double kMinBodySize = 0.7, kMaxBodySize = 2.0;
// Metres the knees must lie in front of (or behind) the hip-ankle lines on average to tell left
// from right.
constexpr double kKneeEvidence = 0.03;

const char* UnitName(double metres) {
  for (const Unit& u : kUnits)
    if (std::abs(u.metres - metres) < 1e-9) return u.name;
  return nullptr;
}

std::string UnitText(double metres) {
  if (const char* name = UnitName(metres)) return name;
  std::ostringstream out;
  out << metres << " m per unit";
  return out.str();
}

std::string AxisText(int axis, int sign) { return std::string(sign < 0 ? "-" : "") + "XYZ"[axis]; }

class Roles {
 public:
  explicit Roles(const std::vector<std::string>& roles) {
    for (size_t j = 0; j < roles.size(); ++j)
      if (!roles[j].empty()) index_.emplace(roles[j], static_cast<int>(j));
  }
  std::optional<int> operator()(const std::string& role) const {
    const auto it = index_.find(role);
    return it == index_.end() ? std::nullopt : std::optional<int>(it->second);
  }

 private:
  std::map<std::string, int> index_;
};

struct Frames {
  const Motion& motion;
  const std::vector<uint8_t>& missing;
  bool Observed(int t, int j) const {
    if (missing.empty()) return true;
    const size_t i = (static_cast<size_t>(t) * motion.num_joints() + j) * 3;
    return !missing[i] && !missing[i + 1] && !missing[i + 2];
  }
  Vec At(int t, int j) const {
    const float* p = motion.at(t, j);
    return {p[0], p[1], p[2]};
  }
};

double Distance(const Vec& a, const Vec& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// (hip, knee, ankle) of each side the roles name completely.
std::vector<std::array<int, 3>> Legs(const Roles& roles) {
  std::vector<std::array<int, 3>> legs;
  for (const char* side : {"left_", "right_"}) {
    const auto hip = roles(std::string(side) + "hip"), knee = roles(std::string(side) + "knee"),
               ankle = roles(std::string(side) + "ankle");
    if (hip && knee && ankle) legs.push_back({*hip, *knee, *ankle});
  }
  return legs;
}

// Median over frames of leg + trunk length, in the values' unit; 0 when the roles are absent.
double BodySize(const Frames& f, const Roles& roles) {
  std::vector<int> trunk;
  for (const char* r : {"pelvis", "spine", "chest", "neck", "head"})
    if (auto j = roles(r)) trunk.push_back(*j);
  const std::vector<std::array<int, 3>> legs = Legs(roles);
  if (trunk.size() < 2 || legs.empty()) return 0;
  std::vector<double> sizes;
  for (int t = 0; t < f.motion.num_frames(); ++t) {
    bool seen = true;
    for (int j : trunk) seen = seen && f.Observed(t, j);
    for (const auto& leg : legs)
      for (int j : leg) seen = seen && f.Observed(t, j);
    if (!seen) continue;
    double size = 0;
    for (size_t i = 1; i < trunk.size(); ++i)
      size += Distance(f.At(t, trunk[i - 1]), f.At(t, trunk[i]));
    double leg_sum = 0;
    for (const auto& leg : legs)
      leg_sum +=
          Distance(f.At(t, leg[0]), f.At(t, leg[1])) + Distance(f.At(t, leg[1]), f.At(t, leg[2]));
    sizes.push_back(size + leg_sum / static_cast<double>(legs.size()));
  }
  return Median(sizes);
}

// The mean over frames of the unit vector pelvis -> head (or neck, chest); nullopt without them.
std::optional<Vec> MeanUp(const Frames& f, const Roles& roles) {
  const auto pelvis = roles("pelvis");
  std::optional<int> top = roles("head");
  if (!top) top = roles("neck");
  if (!top) top = roles("chest");
  if (!pelvis || !top) return std::nullopt;
  Vec sum{0, 0, 0};
  int n = 0;
  for (int t = 0; t < f.motion.num_frames(); ++t) {
    if (!f.Observed(t, *pelvis) || !f.Observed(t, *top)) continue;
    const Vec a = f.At(t, *pelvis), b = f.At(t, *top);
    const double d = Distance(a, b);
    if (d <= 0) continue;
    for (int c = 0; c < 3; ++c) sum[c] += (b[c] - a[c]) / d;
    ++n;
  }
  if (n == 0) return std::nullopt;
  for (double& v : sum) v /= n;
  return sum;
}

// Rotates a vector of the values so that (axis, sign) becomes +Y; a proper rotation.
Vec Rotate(const Vec& p, int axis, int sign) {
  const double x = p[0], y = p[1], z = p[2];
  if (axis == 1) return sign > 0 ? Vec{x, y, z} : Vec{x, -y, -z};
  if (axis == 2) return sign > 0 ? Vec{x, z, -y} : Vec{x, -z, y};
  return sign > 0 ? Vec{-y, x, z} : Vec{y, -x, z};
}

// The inverse of Rotate.
Vec Unrotate(const Vec& p, int axis, int sign) {
  const double x = p[0], y = p[1], z = p[2];
  if (axis == 1) return sign > 0 ? Vec{x, y, z} : Vec{x, -y, -z};
  if (axis == 2) return sign > 0 ? Vec{x, -z, y} : Vec{x, z, -y};
  return sign > 0 ? Vec{y, -x, z} : Vec{-y, x, z};
}

// [joint] -> the joint whose values it takes: its left/right partner when `swap`, else itself.
std::vector<int> Partners(const std::vector<std::string>& roles, bool swap) {
  const int J = static_cast<int>(roles.size());
  std::vector<int> partner(static_cast<size_t>(J));
  for (int j = 0; j < J; ++j) partner[static_cast<size_t>(j)] = j;
  if (!swap) return partner;
  std::map<std::string, int> index;
  for (int j = 0; j < J; ++j) index[roles[static_cast<size_t>(j)]] = j;
  for (int j = 0; j < J; ++j) {
    const std::string& r = roles[static_cast<size_t>(j)];
    std::string other;
    if (r.rfind("left_", 0) == 0) other = "right_" + r.substr(5);
    if (r.rfind("right_", 0) == 0) other = "left_" + r.substr(6);
    const auto it = index.find(other);
    if (!other.empty() && it != index.end()) partner[static_cast<size_t>(j)] = it->second;
  }
  return partner;
}

// Mean over frames of how far each knee lies in front of its hip-ankle line, the front taken
// from the labels (left hip minus right hip, crossed with up), metres; and the mean of its size.
std::optional<std::pair<double, double>> KneeEvidence(const Frames& f, const Roles& roles,
                                                      const BodyFrame& frame) {
  const auto lh = roles("left_hip"), rh = roles("right_hip");
  if (!lh || !rh) return std::nullopt;
  const std::vector<std::array<int, 3>> legs = Legs(roles);
  if (legs.empty()) return std::nullopt;
  auto at = [&](int t, int j) {
    Vec p = Rotate(f.At(t, j), frame.up_axis, frame.up_sign);
    for (double& v : p) v *= frame.scale;
    return p;
  };
  double sum = 0, sum_abs = 0;
  int n = 0;
  for (int t = 0; t < f.motion.num_frames(); ++t) {
    bool seen = f.Observed(t, *lh) && f.Observed(t, *rh);
    for (const auto& leg : legs)
      for (int j : leg) seen = seen && f.Observed(t, j);
    if (!seen) continue;
    const Vec l = at(t, *lh), r = at(t, *rh);
    Vec front{-(l[2] - r[2]), 0, l[0] - r[0]};  // (left - right) x up, on the ground plane
    const double norm = std::hypot(front[0], front[2]);
    if (norm <= 0) continue;
    for (double& v : front) v /= norm;
    double e = 0;
    for (const auto& leg : legs) {
      const Vec hip = at(t, leg[0]), knee = at(t, leg[1]), ankle = at(t, leg[2]);
      for (int c = 0; c < 3; ++c) e += (knee[c] - 0.5 * (hip[c] + ankle[c])) * front[c];
    }
    e /= static_cast<double>(legs.size());
    sum += e;
    sum_abs += std::abs(e);
    ++n;
  }
  if (n == 0) return std::nullopt;
  return std::make_pair(sum / n, sum_abs / n);
}

}  // namespace

std::pair<int, int> ParseUpAxis(const std::string& up) {
  const UpAxis u = ParseUp(up);
  return {u.axis, u.sign};
}

double ParseLengthUnit(const std::string& unit) {
  if (unit.empty() || unit == "auto") return 0;
  for (const Unit& u : kUnits)
    if (unit == u.flag || unit == u.name) return u.metres;
  throw std::invalid_argument("unit '" + unit + "': expected auto, m, cm, mm or in");
}

std::string BodyFrame::Describe() const {
  std::string text = UnitText(unit) + ", " + AxisText(up_axis, up_sign) + " up";
  if (swapped) text += ", left/right exchanged";
  return text;
}

bool BodyFrame::IsIdentity(double read_scale) const {
  return std::abs(unit - read_scale) < 1e-12 && up_axis == target_axis && up_sign == target_sign &&
         !swapped;
}

BodyFrame DetectBodyFrame(const Motion& motion, const std::vector<uint8_t>& missing,
                          const std::vector<std::string>& roles_of_joints,
                          const BodyFrameOptions& options) {
  if (roles_of_joints.size() != static_cast<size_t>(motion.num_joints())) {
    throw std::invalid_argument("DetectBodyFrame: expected a role per joint (" +
                                std::to_string(motion.num_joints()) + "), got " +
                                std::to_string(roles_of_joints.size()));
  }
  const Roles roles(roles_of_joints);
  const Frames f{motion, missing};
  BodyFrame frame;
  frame.unit = options.read_scale;

  // Unit: the body's size in file units against people's.
  const double size_read = BodySize(f, roles);
  const double size_file = size_read / options.read_scale;
  if (options.unit > 0) {
    frame.unit = options.unit;
  } else if (size_file > 0) {
    bool found = false;
    for (const Unit& u : kUnits) {
      const double metres = size_file * u.metres;
      if (metres >= kMinBodySize && metres <= kMaxBodySize) {
        frame.unit = u.metres;
        frame.unit_detected = found = true;
        break;
      }
    }
    if (!found) {
      std::ostringstream w;
      w << "the body's leg + trunk measure " << size_file << " file units, a human size ("
        << kMinBodySize << "-" << kMaxBodySize << " m) in none of m, cm, mm, in: kept as read ("
        << UnitText(options.read_scale) << "); pass --unit to say which";
      frame.warnings.push_back(w.str());
    }
  }
  frame.scale = frame.unit / options.read_scale;
  frame.body_size = size_read * frame.scale;

  // Up: the axis the trunk points along.
  if (!options.up.empty() && options.up != "auto") {
    std::tie(frame.up_axis, frame.up_sign) = ParseUpAxis(options.up);
  } else if (const auto up = MeanUp(f, roles)) {
    int axis = 0;
    for (int c = 1; c < 3; ++c)
      if (std::abs((*up)[c]) > std::abs((*up)[axis])) axis = c;
    if (std::abs((*up)[axis]) >= 0.7) {
      frame.up_axis = axis;
      frame.up_sign = (*up)[axis] > 0 ? 1 : -1;
      frame.up_detected = true;
      if (axis == 1 && frame.up_sign < 0) {
        frame.warnings.push_back(
            "the motion is upside down (the head below the pelvis along Y): turned over; pass "
            "--up y to keep it");
      }
    } else {
      std::ostringstream w;
      w << "no axis points from the pelvis to the head (mean direction " << (*up)[0] << ", "
        << (*up)[1] << ", " << (*up)[2] << "): Y kept as up; pass --up to say which";
      frame.warnings.push_back(w.str());
    }
  }

  if (options.target_up.empty()) {
    frame.target_axis = frame.up_axis, frame.target_sign = frame.up_sign;
  } else {
    std::tie(frame.target_axis, frame.target_sign) = ParseUpAxis(options.target_up);
  }

  // Left/right: knees bend forward.
  if (!options.left_right.empty() && options.left_right != "auto") {
    if (options.left_right != "as-labelled" && options.left_right != "swapped") {
      throw std::invalid_argument("left/right '" + options.left_right +
                                  "': expected auto, as-labelled or swapped");
    }
    frame.swapped = options.left_right == "swapped";
  } else if (const auto e = KneeEvidence(f, roles, frame)) {
    const auto [mean, mean_abs] = *e;
    frame.knee_forward = mean;
    // Decided only well beyond what a knee can hyperextend (3 cm off the line is about 8 degrees
    // for a 0.42 m thigh), and when most frames agree.
    if (std::abs(mean) >= kKneeEvidence && std::abs(mean) >= 0.5 * mean_abs) {
      frame.left_right_detected = true;
      frame.swapped = mean < 0;
      if (frame.swapped) {
        frame.warnings.push_back(
            "the left/right labels disagree with the body (its knees bend backwards for the "
            "sides given): exchanged; pass --left-right as-labelled to keep them");
      }
    }
  }
  return frame;
}

Motion ToModelFrame(const Motion& motion, const BodyFrame& frame,
                    const std::vector<std::string>& roles, std::vector<uint8_t>* missing) {
  const int T = motion.num_frames(), J = motion.num_joints();
  const std::vector<int> partner = Partners(roles, frame.swapped);
  std::vector<float> out(motion.positions().size());
  std::vector<uint8_t> mask = missing ? *missing : std::vector<uint8_t>();
  for (int t = 0; t < T; ++t) {
    for (int j = 0; j < J; ++j) {
      const int from = partner[static_cast<size_t>(j)];
      const float* p = motion.at(t, from);
      Vec v = Unrotate(Rotate({p[0], p[1], p[2]}, frame.up_axis, frame.up_sign), frame.target_axis,
                       frame.target_sign);
      const size_t o = (static_cast<size_t>(t) * J + j) * 3,
                   i = (static_cast<size_t>(t) * J + from) * 3;
      for (int c = 0; c < 3; ++c) {
        out[o + c] = static_cast<float>(v[c] * frame.scale);
        if (missing && !missing->empty()) mask[o + c] = (*missing)[i + c];
      }
    }
  }
  if (missing) *missing = std::move(mask);
  return Motion(motion.skeleton_ptr(), motion.fps(), std::move(out));
}

Motion FromModelFrame(const Motion& motion, const BodyFrame& frame,
                      const std::vector<std::string>& roles) {
  const int T = motion.num_frames(), J = motion.num_joints();
  const std::vector<int> partner = Partners(roles, frame.swapped);
  std::vector<float> out(motion.positions().size());
  for (int t = 0; t < T; ++t) {
    for (int j = 0; j < J; ++j) {
      const float* p = motion.at(t, partner[static_cast<size_t>(j)]);
      const Vec v = Unrotate(Rotate({p[0] / frame.scale, p[1] / frame.scale, p[2] / frame.scale},
                                    frame.target_axis, frame.target_sign),
                             frame.up_axis, frame.up_sign);
      for (int c = 0; c < 3; ++c)
        out[(static_cast<size_t>(t) * J + j) * 3 + c] = static_cast<float>(v[c]);
    }
  }
  return Motion(motion.skeleton_ptr(), motion.fps(), std::move(out));
}

}  // namespace motionfork
