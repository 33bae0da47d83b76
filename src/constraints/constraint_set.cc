#include "constraints/constraint_set.h"

#include <map>
#include <stdexcept>
#include <tuple>

#include "core/enum_names.h"
#include "core/error.h"

namespace motionfork {
namespace {

std::string Substitute(std::string name, const std::string& side, const std::string& other) {
  for (const auto& [ph, value] : {std::make_pair(std::string("{side}"), side),
                                  std::make_pair(std::string("{other}"), other)}) {
    for (size_t at = name.find(ph); at != std::string::npos;
         at = name.find(ph, at + value.size())) {
      name.replace(at, ph.size(), value);
    }
  }
  return name;
}

// One instance (left, right or the only one) of a spec constraint being compiled.
struct Instance {
  std::string side_token, other_token;
  bool flip = false;        // swap every cross product's operands (right-side instance)
  std::vector<int> joints;  // joints in visiting order, for the mirror check
};

class Compiler {
 public:
  Compiler(const Skeleton& skeleton, const std::string& source, std::vector<VectorOp>* ops)
      : skeleton_(skeleton), source_(source), ops_(ops) {}

  // Returns the register holding e; *text receives the resolved expression.
  int Emit(const VectorExpr& e, Instance* inst, const ConstraintSpec& c, std::string* text) {
    if (e.kind == VectorExpr::Kind::kBone) {
      const int from = Joint(Substitute(e.from, inst->side_token, inst->other_token), c);
      const int to = Joint(Substitute(e.to, inst->side_token, inst->other_token), c);
      if (from == to) {
        Fail(c, "bone(" + e.from + ", " + e.to + ") joins joint '" + skeleton_.joint_name(from) +
                    "' to itself: the vector is zero by construction");
      }
      inst->joints.push_back(from);
      inst->joints.push_back(to);
      *text = "bone(" + skeleton_.joint_name(from) + ", " + skeleton_.joint_name(to) + ")";
      return Op(VectorOp::Kind::kBone, from, to);
    }
    if (e.operands.size() != 2) Fail(c, "normal(u, v) needs exactly two vectors");
    std::string tu, tv;
    const int u = Emit(e.operands[0], inst, c, &tu);
    const int v = Emit(e.operands[1], inst, c, &tv);
    if (u == v) {
      Fail(c, "normal(" + tu + ", " + tv + ") crosses a vector with itself: zero by construction");
    }
    *text = inst->flip ? "normal(" + tv + ", " + tu + ")" : "normal(" + tu + ", " + tv + ")";
    return inst->flip ? Op(VectorOp::Kind::kCross, v, u) : Op(VectorOp::Kind::kCross, u, v);
  }

  [[noreturn]] void Fail(const ConstraintSpec& c, const std::string& what) const {
    throw FormatError(FormatMessage(source_, c.location, "constraint '" + c.name + "': " + what));
  }

 private:
  int Joint(const std::string& name, const ConstraintSpec& c) const {
    if (const auto j = skeleton_.Find(name)) return *j;
    std::string known;
    for (const std::string& n : skeleton_.joint_names()) known += (known.empty() ? "" : ", ") + n;
    Fail(c,
         "unknown joint '" + name + "' (skeleton '" + skeleton_.name() + "' has: " + known + ")");
  }
  int Op(VectorOp::Kind kind, int x, int y) {
    const auto key = std::make_tuple(static_cast<int>(kind), x, y);
    const auto it = index_.find(key);
    if (it != index_.end()) return it->second;
    ops_->push_back(VectorOp{kind, x, y});
    const int r = static_cast<int>(ops_->size()) - 1;
    index_[key] = r;
    return r;
  }

  const Skeleton& skeleton_;
  const std::string& source_;
  std::vector<VectorOp>* ops_;
  std::map<std::tuple<int, int, int>, int> index_;
};

}  // namespace

const char* ToString(Side side) {
  static constexpr EnumName<Side> kNames[] = {
      {Side::kNone, "none"}, {Side::kLeft, "left"}, {Side::kRight, "right"}};
  return NameOf(side, kNames);
}

std::string ToString(const VectorExpr& e) {
  if (e.kind == VectorExpr::Kind::kBone) return "bone(" + e.from + ", " + e.to + ")";
  std::string out = "normal(";
  for (size_t k = 0; k < e.operands.size(); ++k) out += (k ? ", " : "") + ToString(e.operands[k]);
  return out + ")";
}

ConstraintSet ConstraintSet::Build(const ConstraintSetSpec& spec, const Skeleton& skeleton,
                                   const ConstraintBuildOptions& options) {
  ConstraintSet set;
  set.spec_ = spec;
  set.skeleton_name_ = skeleton.name();
  set.num_joints_ = skeleton.num_joints();
  Compiler compiler(skeleton, spec.source, &set.ops_);
  if (spec.left_token.empty() || spec.left_token == spec.right_token) {
    throw FormatError(
        FormatMessage(spec.source, "",
                      "the side tokens must be two different, non-empty strings, got '" +
                          spec.left_token + "' and '" + spec.right_token + "'"));
  }
  const bool can_mirror = !skeleton.left_right_pairs().empty();
  std::map<std::string, int> names;
  for (size_t i = 0; i < spec.constraints.size(); ++i) {
    const ConstraintSpec& c = spec.constraints[i];
    if (c.has_range) {
      if (!(c.lower_deg >= 0 && c.lower_deg <= c.upper_deg && c.upper_deg <= 180)) {
        compiler.Fail(c, "range [" + std::to_string(c.lower_deg) + ", " +
                             std::to_string(c.upper_deg) +
                             "] breaks the rule 0 <= lower <= upper <= 180 (degrees)");
      }
    } else if (options.require_ranges) {
      compiler.Fail(c, "missing range [lower, upper] (degrees)");
    }
    std::vector<Instance> instances;
    if (c.per_side) {
      instances.push_back(Instance{spec.left_token, spec.right_token, false, {}});
      instances.push_back(Instance{spec.right_token, spec.left_token, true, {}});
    } else {
      instances.push_back(Instance{spec.left_token, spec.right_token, false, {}});
    }
    const int first = static_cast<int>(set.constraints_.size());
    for (size_t k = 0; k < instances.size(); ++k) {
      Instance& inst = instances[k];
      Constraint out;
      out.base_name = c.name;
      out.side = !c.per_side ? Side::kNone : (k == 0 ? Side::kLeft : Side::kRight);
      out.name = c.per_side ? c.name + "_" + inst.side_token : c.name;
      out.spec_index = static_cast<int>(i);
      out.mirror = c.per_side ? first + (1 - static_cast<int>(k)) : first;
      out.has_range = c.has_range;
      out.lower_deg = c.has_range ? c.lower_deg : 0.0;
      out.upper_deg = c.has_range ? c.upper_deg : 180.0;
      out.a = compiler.Emit(c.a, &inst, c, &out.a_text);
      out.b = compiler.Emit(c.b, &inst, c, &out.b_text);
      if (out.a == out.b) {
        compiler.Fail(c,
                      "vectors a and b are the same (" + out.a_text + "): the angle is always 0");
      }
      if (!names.emplace(out.name, static_cast<int>(set.constraints_.size())).second) {
        compiler.Fail(c, "the name '" + out.name + "' is used twice");
      }
      set.constraints_.push_back(std::move(out));
    }
    if (c.per_side && can_mirror) {
      const std::vector<int>& l = instances[0].joints;
      const std::vector<int>& r = instances[1].joints;
      for (size_t p = 0; p < l.size() && p < r.size(); ++p) {
        if (skeleton.Mirror(l[p]) != r[p]) {
          compiler.Fail(c,
                        "the right-side instance is not the mirror image of the left one: it "
                        "uses joint '" +
                            skeleton.joint_name(r[p]) + "' where the mirror of '" +
                            skeleton.joint_name(l[p]) + "' ('" +
                            skeleton.joint_name(skeleton.Mirror(l[p])) +
                            "') belongs; write paired joints with {side} / {other}");
        }
      }
    }
  }
  return set;
}

int ConstraintSet::Find(const std::string& constraint_name) const {
  for (int c = 0; c < num_constraints(); ++c) {
    if (constraints_[c].name == constraint_name) return c;
  }
  return -1;
}

}  // namespace motionfork
