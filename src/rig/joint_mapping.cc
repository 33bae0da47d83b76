#include "rig/joint_mapping.h"

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

namespace motionfork {
namespace {

// A rig's joints by normalized name (the first joint of a name wins).
std::map<std::string, int> NameIndex(const Skeleton& s) {
  std::map<std::string, int> index;
  for (int j = 0; j < s.num_joints(); ++j) index.emplace(NormalizeJointName(s.joint_name(j)), j);
  return index;
}

using Weighted = std::vector<std::pair<int, double>>;

// How `convention` makes `role` on a rig: its first variant whose joints the rig has, else the
// role derived from others (depth-limited: derived roles are one or two steps deep).
std::optional<Weighted> Resolve(const RigConvention& convention, const std::string& role,
                                const std::map<std::string, int>& index, int depth = 0) {
  const auto it = convention.roles.find(role);
  if (it != convention.roles.end()) {
    for (const JointBlend& blend : it->second) {
      Weighted w;
      for (size_t i = 0; i < blend.joints.size(); ++i) {
        const auto j = index.find(NormalizeJointName(blend.joints[i]));
        if (j == index.end()) break;
        w.emplace_back(j->second, blend.weights[i]);
      }
      if (w.size() == blend.joints.size()) return w;
    }
  }
  if (depth >= 2) return std::nullopt;
  const auto& derived = DerivedRole(role);
  if (derived.empty()) return std::nullopt;
  std::map<int, double> sum;
  for (const auto& [part, weight] : derived) {
    const auto w = Resolve(convention, part, index, depth + 1);
    if (!w) return std::nullopt;
    for (const auto& [j, v] : *w) sum[j] += weight * v;
  }
  return Weighted(sum.begin(), sum.end());
}

// How well a convention explains a rig: how many of the names it lists (all variants, `also`)
// the rig has; between two that explain as many joints, the one that names more of the target's
// roles by a joint of the rig (rather than making them from others: an Unreal 4 mannequin's
// spine_03 is its chest, which the Unreal 5 convention would make from the shoulders); then
// which share of its names the rig has (the one that lists fewer others is the rig's own:
// HumanEva's 15 rather than Human3.6M's 32).
struct Score {
  int matched = -1;
  int named_roles = 0;
  double share = 0;
  bool operator>(const Score& o) const {
    if (matched != o.matched) return matched > o.matched;
    if (named_roles != o.named_roles) return named_roles > o.named_roles;
    return share > o.share;
  }
  bool operator==(const Score& o) const {
    return matched == o.matched && named_roles == o.named_roles && share == o.share;
  }
};

Score ScoreOf(const RigConvention& convention, const std::map<std::string, int>& index) {
  std::set<std::string> names;
  for (const auto& [role, variants] : convention.roles)
    for (const JointBlend& b : variants)
      for (const std::string& n : b.joints) names.insert(NormalizeJointName(n));
  for (const std::string& n : convention.also) names.insert(NormalizeJointName(n));
  Score score{0, 0};
  for (const std::string& n : names) score.matched += index.count(n) ? 1 : 0;
  score.share = names.empty() ? 0 : static_cast<double>(score.matched) / names.size();
  return score;
}

std::string Describe(const Skeleton& from, const Weighted& w) {
  if (w.size() == 1) return from.joint_name(w[0].first);
  std::ostringstream out;
  for (size_t i = 0; i < w.size(); ++i) {
    out << (i ? " + " : "") << w[i].second << " " << from.joint_name(w[i].first);
  }
  return out.str();
}

}  // namespace

NamedRoles RolesOfSkeleton(const Skeleton& skeleton,
                           const std::vector<RigConvention>& conventions) {
  NamedRoles best;
  Score best_score;
  for (const RigConvention& c : conventions) {
    std::map<std::string, std::string> role_of;  // normalized single-joint name -> role
    for (const auto& [role, variants] : c.roles)
      for (const JointBlend& b : variants)
        if (b.joints.size() == 1) role_of.emplace(NormalizeJointName(b.joints[0]), role);
    NamedRoles named{&c, {}};
    for (const std::string& n : skeleton.joint_names()) {
      const auto it = role_of.find(NormalizeJointName(n));
      if (it == role_of.end()) break;
      named.roles.push_back(it->second);
    }
    if (named.roles.size() != static_cast<size_t>(skeleton.num_joints())) continue;
    const Score score = ScoreOf(c, NameIndex(skeleton));
    if (score > best_score) best = named, best_score = score;
  }
  if (!best.convention) {
    throw std::invalid_argument("no rig convention names every joint of skeleton '" +
                                skeleton.name() + "' (configs/rigs/)");
  }
  return best;
}

JointMapping MapJoints(const Skeleton& from, const Skeleton& to,
                       const std::vector<RigConvention>& conventions, const RigConvention* forced) {
  const NamedRoles target = RolesOfSkeleton(to, conventions);
  const std::map<std::string, int> index = NameIndex(from);
  std::vector<const RigConvention*> candidates;
  if (forced) {
    candidates.push_back(forced);
  } else {
    for (const RigConvention& c : conventions) candidates.push_back(&c);
  }
  const RigConvention* best = nullptr;
  Score best_score;
  std::vector<std::string> best_missing;  // of the closest incomplete convention
  Score closest_score;
  const RigConvention* closest = nullptr;
  for (const RigConvention* c : candidates) {
    std::vector<std::string> missing;
    for (const std::string& role : target.roles)
      if (!Resolve(*c, role, index)) missing.push_back(role);
    Score score = ScoreOf(*c, index);
    for (const std::string& role : target.roles) {
      const auto w = Resolve(*c, role, index, /*depth=*/2);  // no derived roles at depth 2
      score.named_roles += w && w->size() == 1;
    }
    if (missing.empty()) {
      if (score > best_score) best = c, best_score = score;
    } else if (score > closest_score ||
               (score == closest_score && missing.size() < best_missing.size())) {
      closest = c, closest_score = score, best_missing = missing;
    }
  }
  if (!best) {
    std::string what =
        "the joints of '" + from.name() + "' (" + std::to_string(from.num_joints()) + ": " +
        from.joint_name(0) + (from.num_joints() > 1 ? ", " + from.joint_name(1) : "") +
        (from.num_joints() > 2 ? ", ..." : "") + ") do not map onto skeleton '" + to.name() + "'";
    if (closest) {
      what += ": read as the " + closest->name + " rig, it lacks ";
      for (size_t i = 0; i < best_missing.size(); ++i) {
        const std::string& role = best_missing[i];
        const auto it = closest->roles.find(role);
        what += (i ? ", " : "") + role;
        if (it != closest->roles.end() && !it->second.empty() && it->second[0].joints.size() == 1) {
          what += " ('" + it->second[0].joints[0] + "')";
        }
      }
    }
    throw std::invalid_argument(what +
                                "; name your joints' roles in a joint map "
                                "(--joint-map FILE, see configs/rigs/README.md)");
  }
  JointMapping m;
  m.source_rig = best->name;
  m.target_rig = target.convention->name;
  m.source_joints = from.num_joints();
  std::vector<bool> used(static_cast<size_t>(from.num_joints()), false);
  for (const std::string& role : target.roles) {
    Weighted w = *Resolve(*best, role, index);
    for (const auto& [j, v] : w) used[static_cast<size_t>(j)] = true;
    m.described.push_back(Describe(from, w));
    m.sources.push_back(std::move(w));
  }
  for (int j = 0; j < from.num_joints(); ++j)
    if (!used[static_cast<size_t>(j)]) m.ignored.push_back(from.joint_name(j));
  return m;
}

Motion ApplyJointMapping(const Motion& motion, const JointMapping& mapping,
                         std::shared_ptr<const Skeleton> to) {
  const int T = motion.num_frames(), Jf = motion.num_joints(),
            Jt = static_cast<int>(mapping.sources.size());
  if (Jf != mapping.source_joints || to->num_joints() != Jt) {
    throw std::invalid_argument("ApplyJointMapping: expected " +
                                std::to_string(mapping.source_joints) + " -> " +
                                std::to_string(Jt) + " joints, got " + std::to_string(Jf) + " -> " +
                                std::to_string(to->num_joints()));
  }
  const std::vector<float>& in = motion.positions();
  std::vector<float> out(static_cast<size_t>(T) * Jt * 3, 0.0f);
  for (int t = 0; t < T; ++t) {
    for (int j = 0; j < Jt; ++j) {
      for (int c = 0; c < 3; ++c) {
        double v = 0;
        for (const auto& [s, w] : mapping.sources[static_cast<size_t>(j)])
          v += w * in[(static_cast<size_t>(t) * Jf + s) * 3 + c];
        out[(static_cast<size_t>(t) * Jt + j) * 3 + c] = static_cast<float>(v);
      }
    }
  }
  return Motion(std::move(to), motion.fps(), std::move(out));
}

std::vector<uint8_t> ApplyJointMapping(const std::vector<uint8_t>& missing,
                                       const JointMapping& mapping) {
  const size_t Jf = static_cast<size_t>(mapping.source_joints), Jt = mapping.sources.size();
  if (Jf == 0 || missing.size() % (Jf * 3) != 0) {
    throw std::invalid_argument("ApplyJointMapping: a mask of " + std::to_string(missing.size()) +
                                " values is not [T, " + std::to_string(Jf) + ", 3]");
  }
  const size_t T = missing.size() / (Jf * 3);
  std::vector<uint8_t> out(T * Jt * 3, 0);
  for (size_t t = 0; t < T; ++t)
    for (size_t j = 0; j < Jt; ++j)
      for (int c = 0; c < 3; ++c)
        for (const auto& [s, w] : mapping.sources[j])
          out[(t * Jt + j) * 3 + c] |= missing[(t * Jf + static_cast<size_t>(s)) * 3 + c];
  return out;
}

}  // namespace motionfork
