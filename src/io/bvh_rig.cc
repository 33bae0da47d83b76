#include "io/bvh_rig.h"

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace motionfork {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// m <- m * R_axis(angle_deg), right-handed (as the reader composes channels).
void RotateRight(double* m, int axis, double angle_deg) {
  const double a = angle_deg * kDeg, s = std::sin(a), c = std::cos(a);
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  for (int r = 0; r < 3; ++r) {
    const double mu = m[3 * r + u], mv = m[3 * r + v];
    m[3 * r + u] = mu * c + mv * s;
    m[3 * r + v] = -mu * s + mv * c;
  }
}

// The node's rotation axes in channel order and where their values sit in the frame.
struct RotationChannels {
  std::array<int, 3> axis{}, slot{};
  int count = 0;
};
RotationChannels RotationsOf(const BvhRig::Node& n) {
  RotationChannels rc;
  for (size_t c = 0; c < n.channels.size(); ++c) {
    if (n.channels[c] < 3 || rc.count == 3) continue;
    rc.axis[rc.count] = n.channels[c] - 3;
    rc.slot[rc.count] = n.first_channel + static_cast<int>(c);
    ++rc.count;
  }
  return rc;
}

// angle + 360 k nearest `near`.
double Nearest(double angle, double near) {
  return angle + 360.0 * std::round((near - angle) / 360.0);
}

std::string Number(double v, int decimals) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(decimals);
  out << (std::abs(v) < 0.5 * std::pow(10.0, -decimals) ? 0.0 : v);
  std::string s = out.str();
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

const char* kChannelName[] = {"Xposition", "Yposition", "Zposition",
                              "Xrotation", "Yrotation", "Zrotation"};

}  // namespace

void RigLocalRotation(const BvhRig::Node& node, const double* values, double* r) {
  for (int k = 0; k < 9; ++k) r[k] = k % 4 == 0 ? 1.0 : 0.0;
  for (size_t c = 0; c < node.channels.size(); ++c) {
    if (node.channels[c] >= 3)
      RotateRight(r, node.channels[c] - 3, values[node.first_channel + static_cast<int>(c)]);
  }
}

BvhRigPose RigForwardKinematics(const BvhRig& rig, const double* values) {
  const size_t n = rig.nodes.size();
  BvhRigPose pose;
  pose.rotation.assign(9 * n, 0.0);
  pose.position.assign(3 * n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const BvhRig::Node& node = rig.nodes[i];
    double local_t[3] = {node.offset[0], node.offset[1], node.offset[2]};
    for (size_t c = 0; c < node.channels.size(); ++c) {
      if (node.channels[c] < 3)
        local_t[node.channels[c]] = values[node.first_channel + static_cast<int>(c)];
    }
    double local_r[9];
    RigLocalRotation(node, values, local_r);
    double* R = pose.rotation.data() + 9 * i;
    double* p = pose.position.data() + 3 * i;
    if (node.parent < 0) {
      for (int k = 0; k < 9; ++k) R[k] = local_r[k];
      for (int a = 0; a < 3; ++a) p[a] = local_t[a];
      continue;
    }
    const double* PR = pose.R(node.parent);
    const double* pp = pose.p(node.parent);
    for (int a = 0; a < 3; ++a) {
      p[a] = pp[a];
      for (int b = 0; b < 3; ++b) {
        p[a] += PR[3 * a + b] * local_t[b];
        double s = 0;
        for (int k = 0; k < 3; ++k) s += PR[3 * a + k] * local_r[3 * k + b];
        R[3 * a + b] = s;
      }
    }
  }
  return pose;
}

bool SetRigLocalRotation(const BvhRig::Node& node, const double* r, double* values) {
  const RotationChannels rc = RotationsOf(node);
  if (rc.count != 3) return false;
  const int i = rc.axis[0], j = rc.axis[1], k = rc.axis[2];
  if (i == j || j == k || i == k) return false;
  // R = R_i(a) R_j(b) R_k(c); e = +1 when (i, j, k) is a cyclic order of (x, y, z).
  const double e = (j == (i + 1) % 3) ? 1.0 : -1.0;
  const auto at = [&](int row, int col) { return r[3 * row + col]; };
  const double sb = std::max(-1.0, std::min(1.0, e * at(i, k)));
  const double b = std::asin(sb);
  double a, c;
  if (std::abs(sb) < 1.0 - 1e-12) {
    a = std::atan2(-e * at(j, k), at(k, k));
    c = std::atan2(-e * at(i, j), at(i, i));
  } else {  // gimbal lock: only a + c (or a - c) is told; keep c where it was
    c = values[rc.slot[2]] * kDeg;
    // With c known, R_i(a) = R R_k(c)^T R_j(b)^T: read a from it.
    double m[9];
    for (int q = 0; q < 9; ++q) m[q] = r[q];
    RotateRight(m, k, -c / kDeg);
    RotateRight(m, j, -b / kDeg);
    const int u = (i + 1) % 3, v = (i + 2) % 3;
    a = std::atan2(m[3 * v + u], m[3 * u + u]);
  }
  // Two triples give the same rotation: (a, b, c) and (a + 180, 180 - b, c + 180).
  const double first[3] = {a / kDeg, b / kDeg, c / kDeg};
  const double second[3] = {a / kDeg + 180.0, 180.0 - b / kDeg, c / kDeg + 180.0};
  double best[3], best_cost = 1e300;
  for (const double* t : {first, second}) {
    double cand[3], cost = 0;
    for (int q = 0; q < 3; ++q) {
      cand[q] = Nearest(t[q], values[rc.slot[q]]);
      cost += std::abs(cand[q] - values[rc.slot[q]]);
    }
    if (cost < best_cost) {
      best_cost = cost;
      for (int q = 0; q < 3; ++q) best[q] = cand[q];
    }
  }
  for (int q = 0; q < 3; ++q) values[rc.slot[q]] = best[q];
  return true;
}

std::string BvhRigText(const BvhRig& rig, const std::vector<double>& values, double frame_time,
                       int decimals) {
  if (rig.num_channels > 0 && values.size() % rig.num_channels != 0) {
    throw std::invalid_argument("BvhRigText: expected whole frames of " +
                                std::to_string(rig.num_channels) + " values, got " +
                                std::to_string(values.size()));
  }
  std::ostringstream out;
  out << "HIERARCHY\n";
  std::vector<int> depth(rig.nodes.size(), 0);
  const auto close_to = [&](int level, int open) {
    for (int d = open - 1; d >= level; --d) out << std::string(2 * d, ' ') << "}\n";
  };
  int open = 0;  // braces open
  for (size_t n = 0; n < rig.nodes.size(); ++n) {
    const BvhRig::Node& node = rig.nodes[n];
    const int d = node.parent < 0 ? 0 : depth[node.parent] + 1;
    depth[n] = d;
    close_to(d, open);
    open = d;
    const std::string pad(2 * d, ' ');
    if (node.end_site) {
      out << pad << "End Site\n";
    } else {
      out << pad << (node.parent < 0 ? "ROOT " : "JOINT ") << node.name << "\n";
    }
    out << pad << "{\n" << pad << "  OFFSET";
    for (double o : node.offset) out << " " << Number(o, decimals);
    out << "\n";
    if (!node.end_site) {
      out << pad << "  CHANNELS " << node.channels.size();
      for (int c : node.channels) out << " " << kChannelName[c];
      out << "\n";
    }
    ++open;
  }
  close_to(0, open);
  const size_t frames = rig.num_channels ? values.size() / rig.num_channels : 0;
  out << "MOTION\nFrames: " << frames << "\nFrame Time: " << Number(frame_time, 8) << "\n";
  for (size_t t = 0; t < frames; ++t) {
    for (int c = 0; c < rig.num_channels; ++c)
      out << (c ? " " : "") << Number(values[t * rig.num_channels + c], decimals);
    out << "\n";
  }
  return out.str();
}

}  // namespace motionfork
