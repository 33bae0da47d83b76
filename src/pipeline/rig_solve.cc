#include "pipeline/rig_solve.h"

#include <algorithm>
#include <cmath>

#include "core/rotation_fit.h"
#include "io/bvh_rig.h"

namespace motionfork::pipeline {

RigSolver::RigSolver(const BvhRig& rig, std::vector<uint8_t> targeted)
    : rig_(rig), targeted_(std::move(targeted)), nearest_(rig.nodes.size()) {
  // Nodes come parents first: walk up from every targeted node, adding it to the ancestors until
  // (and including) the first targeted one.
  for (size_t n = 0; n < rig.nodes.size(); ++n) {
    if (!targeted_[n]) continue;
    for (int a = rig.nodes[n].parent; a >= 0; a = rig.nodes[static_cast<size_t>(a)].parent) {
      nearest_[static_cast<size_t>(a)].push_back(static_cast<int>(n));
      if (targeted_[static_cast<size_t>(a)]) break;
    }
  }
}

namespace {

void Translate(const BvhRig::Node& root, const double* by, double* values) {
  for (size_t c = 0; c < root.channels.size(); ++c) {
    if (root.channels[c] < 3)
      values[root.first_channel + static_cast<int>(c)] += by[root.channels[c]];
  }
}

bool HasPositionChannels(const BvhRig::Node& n) {
  return std::any_of(n.channels.begin(), n.channels.end(), [](int c) { return c < 3; });
}

}  // namespace

void RigSolver::Solve(const std::vector<double>& targets, double* values) const {
  // A joint between a turning one and its target (a spine joint no model joint names) is held
  // while the one above turns, so one pass leaves it short; passes repeat while they gain.
  double miss = Miss(targets, values);
  for (int pass = 0; pass < kMaxPasses && miss > 1e-9; ++pass) {
    std::vector<double> before(values, values + rig_.num_channels);
    Pass(targets, values);
    const double now = Miss(targets, values);
    if (now > miss * (1 - 1e-3)) {
      if (now > miss) std::copy(before.begin(), before.end(), values);
      break;
    }
    miss = now;
  }
}

void RigSolver::Pass(const std::vector<double>& targets, double* values) const {
  const auto target = [&](int n) { return targets.data() + 3 * n; };
  // The root onto its target (or its nearest targeted descendant's).
  const auto place_root = [&] {
    const BvhRig::Node& root = rig_.nodes[0];
    if (!HasPositionChannels(root)) return;
    const int anchor = targeted_[0] ? 0 : (nearest_[0].empty() ? -1 : nearest_[0][0]);
    if (anchor < 0) return;
    const BvhRigPose pose = RigForwardKinematics(rig_, values);
    double by[3];
    for (int a = 0; a < 3; ++a) by[a] = target(anchor)[a] - pose.p(anchor)[a];
    Translate(root, by, values);
  };
  place_root();
  for (size_t n = 0; n < rig_.nodes.size(); ++n) {
    const std::vector<int>& below = nearest_[n];
    if (below.empty() || (n == 0 && !targeted_[0])) continue;
    const BvhRigPose pose = RigForwardKinematics(rig_, values);
    std::vector<double> u, v, w;
    for (int d : below) {
      double len = 0;
      for (int a = 0; a < 3; ++a) {
        u.push_back(pose.p(d)[a] - pose.p(static_cast<int>(n))[a]);
        v.push_back(target(d)[a] - pose.p(static_cast<int>(n))[a]);
        len += u.back() * u.back();
      }
      w.push_back(std::sqrt(len));
    }
    double turn[9];
    FitRotation(u, v, w, turn);
    // New world rotation turn * R; local = parent's world rotation^T * that.
    const double* R = pose.R(static_cast<int>(n));
    double world[9], local[9];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        double s = 0;
        for (int k = 0; k < 3; ++k) s += turn[3 * a + k] * R[3 * k + b];
        world[3 * a + b] = s;
      }
    const int parent = rig_.nodes[n].parent;
    if (parent < 0) {
      std::copy(world, world + 9, local);
    } else {
      const double* P = pose.R(parent);
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          double s = 0;
          for (int k = 0; k < 3; ++k) s += P[3 * k + a] * world[3 * k + b];
          local[3 * a + b] = s;
        }
    }
    SetRigLocalRotation(rig_.nodes[n], local, values);
    if (n == 0) place_root();
  }
}

double RigSolver::Miss(const std::vector<double>& targets, const double* values) const {
  const BvhRigPose pose = RigForwardKinematics(rig_, values);
  double worst = 0;
  for (size_t n = 0; n < rig_.nodes.size(); ++n) {
    if (!targeted_[n]) continue;
    double d2 = 0;
    for (int a = 0; a < 3; ++a)
      d2 += std::pow(pose.p(static_cast<int>(n))[a] - targets[3 * n + a], 2);
    worst = std::max(worst, std::sqrt(d2));
  }
  return worst;
}

}  // namespace motionfork::pipeline
