#include "constraints/torch/angle_penalty.h"

#include <torch/torch.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "constraints/vector_registers.h"

namespace motionfork {
namespace {

constexpr double kPi = 3.14159265358979323846;

torch::Tensor Longs(const std::vector<int64_t>& v) {
  return torch::tensor(v, torch::dtype(torch::kLong));
}

// ---- Fused CPU kernel ---------------------------------------------------------------------
//
// Per frame: the set's program evaluated into registers (as the checker does), the penalty of
// every constraint, and in the backward pass the same registers recomputed and the gradient
// propagated back through the program in reverse order:
//   cos = a.b / (|a||b|):  dcos/da = b / (|a||b|) - cos a / |a|^2  (and symmetrically for b)
//   n = u x v:             dL/du = v x g,  dL/dv = g x u            (g = dL/dn)
//   bone = p[to] - p[from]: dL/dp[to] += g, dL/dp[from] -= g
// Registers are recomputed rather than stored: 4 numbers x R registers a frame would cost more
// memory traffic than the arithmetic.

struct Program {
  const int64_t* ops;    // [R, 3]
  const int64_t* cons;   // [C, 2]
  const double* bounds;  // [C, 4]
  int64_t R, C, J;
  double min_len2, min_sin2;
};

template <typename T>
struct Registers {
  std::vector<T> v;          // [R, 4]: x, y, z, squared length
  std::vector<uint8_t> bad;  // [R]: undefined
  explicit Registers(int64_t R) : v(4 * R), bad(R) {}
  void Evaluate(const Program& p, const T* f) {
    const T min_len2 = static_cast<T>(p.min_len2), min_sin2 = static_cast<T>(p.min_sin2);
    for (int64_t r = 0; r < p.R; ++r) {
      const int64_t* op = p.ops + 3 * r;
      T* out = &v[4 * r];
      if (op[0] == 0) {
        bad[r] = BoneRegister(f, op[1], op[2], min_len2, out);
      } else {
        bad[r] =
            CrossRegister(&v[4 * op[1]], &v[4 * op[2]], bad[op[1]] | bad[op[2]], min_sin2, out);
      }
    }
  }
};

// d penalty / d cos for constraint c at cosine x (0 inside the range or at an unapplied bound),
// and the penalty itself.
template <typename T>
inline T Penalty(const double* bound, T x, T* slope) {
  const T lo = static_cast<T>(bound[0]), hi = static_cast<T>(bound[1]);
  if (bound[2] != 0 && x > lo) {
    *slope = 2 * (x - lo);
    return (x - lo) * (x - lo);
  }
  if (bound[3] != 0 && x < hi) {
    *slope = 2 * (x - hi);
    return (hi - x) * (hi - x);
  }
  *slope = 0;
  return 0;
}

template <typename T>
void FusedForward(const Program& p, const T* poses, int64_t n, T* out) {
  at::parallel_for(0, n, 256, [&](int64_t begin, int64_t end) {
    Registers<T> reg(p.R);
    for (int64_t t = begin; t < end; ++t) {
      reg.Evaluate(p, poses + t * p.J * 3);
      T* row = out + t * p.C;
      for (int64_t c = 0; c < p.C; ++c) {
        const int64_t a = p.cons[2 * c], b = p.cons[2 * c + 1];
        if (reg.bad[a] | reg.bad[b]) {
          row[c] = 0;
          continue;
        }
        const T* u = &reg.v[4 * a];
        const T* w = &reg.v[4 * b];
        const T x = (u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) / std::sqrt(u[3] * w[3]);
        T slope;
        row[c] = Penalty(p.bounds + 4 * c, x, &slope);
      }
    }
  });
}

template <typename T>
void FusedBackward(const Program& p, const T* poses, const T* grad_out, int64_t n, T* grad) {
  at::parallel_for(0, n, 256, [&](int64_t begin, int64_t end) {
    Registers<T> reg(p.R);
    std::vector<T> g(3 * p.R);
    for (int64_t t = begin; t < end; ++t) {
      reg.Evaluate(p, poses + t * p.J * 3);
      std::fill(g.begin(), g.end(), T(0));
      bool any = false;
      const T* gout = grad_out + t * p.C;
      for (int64_t c = 0; c < p.C; ++c) {
        const int64_t a = p.cons[2 * c], b = p.cons[2 * c + 1];
        if (gout[c] == 0 || (reg.bad[a] | reg.bad[b])) continue;
        const T* u = &reg.v[4 * a];
        const T* w = &reg.v[4 * b];
        const T inv = 1 / std::sqrt(u[3] * w[3]);
        const T x = (u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) * inv;
        T slope;
        Penalty(p.bounds + 4 * c, x, &slope);
        if (slope == 0) continue;
        any = true;
        const T s = gout[c] * slope;
        const T ka = x / u[3], kb = x / w[3];
        for (int k = 0; k < 3; ++k) {
          g[3 * a + k] += s * (w[k] * inv - ka * u[k]);
          g[3 * b + k] += s * (u[k] * inv - kb * w[k]);
        }
      }
      if (!any) continue;
      T* gp = grad + t * p.J * 3;
      for (int64_t r = p.R - 1; r >= 0; --r) {
        const T* gr = &g[3 * r];
        if (gr[0] == 0 && gr[1] == 0 && gr[2] == 0) continue;
        const int64_t* op = p.ops + 3 * r;
        if (op[0] == 0) {
          for (int k = 0; k < 3; ++k) {
            gp[3 * op[2] + k] += gr[k];
            gp[3 * op[1] + k] -= gr[k];
          }
        } else {
          const T* u = &reg.v[4 * op[1]];
          const T* w = &reg.v[4 * op[2]];
          T* gu = &g[3 * op[1]];
          T* gw = &g[3 * op[2]];
          // dL/du = w x g, dL/dw = g x u
          gu[0] += w[1] * gr[2] - w[2] * gr[1];
          gu[1] += w[2] * gr[0] - w[0] * gr[2];
          gu[2] += w[0] * gr[1] - w[1] * gr[0];
          gw[0] += gr[1] * u[2] - gr[2] * u[1];
          gw[1] += gr[2] * u[0] - gr[0] * u[2];
          gw[2] += gr[0] * u[1] - gr[1] * u[0];
        }
      }
    }
  });
}

Program MakeProgram(const torch::Tensor& ops, const torch::Tensor& cons,
                    const torch::Tensor& bounds, int64_t joints, double min_len2, double min_sin2) {
  return Program{ops.data_ptr<int64_t>(),
                 cons.data_ptr<int64_t>(),
                 bounds.data_ptr<double>(),
                 ops.size(0),
                 cons.size(0),
                 joints,
                 min_len2,
                 min_sin2};
}

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

// poses [N, J, 3] contiguous CPU float/double -> [N, C].
class FusedPenaltyFn : public torch::autograd::Function<FusedPenaltyFn> {
 public:
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& poses,
                               const torch::Tensor& ops, const torch::Tensor& cons,
                               const torch::Tensor& bounds, double min_len2, double min_sin2) {
    const Program p = MakeProgram(ops, cons, bounds, poses.size(1), min_len2, min_sin2);
    torch::Tensor out = torch::empty({poses.size(0), p.C}, poses.options());
    AT_DISPATCH_FLOATING_TYPES(poses.scalar_type(), "FusedPenaltyForward", [&] {
      FusedForward<scalar_t>(p, poses.data_ptr<scalar_t>(), poses.size(0),
                             out.data_ptr<scalar_t>());
    });
    ctx->save_for_backward({poses, ops, cons, bounds});
    ctx->saved_data["min_len2"] = min_len2;
    ctx->saved_data["min_sin2"] = min_sin2;
    return out;
  }
  static variable_list backward(AutogradContext* ctx, variable_list grad_outputs) {
    const auto saved = ctx->get_saved_variables();
    const torch::Tensor& poses = saved[0];
    const Program p =
        MakeProgram(saved[1], saved[2], saved[3], poses.size(1),
                    ctx->saved_data["min_len2"].toDouble(), ctx->saved_data["min_sin2"].toDouble());
    const torch::Tensor grad_out = grad_outputs[0].contiguous();
    torch::Tensor grad = torch::zeros_like(poses);
    AT_DISPATCH_FLOATING_TYPES(poses.scalar_type(), "FusedPenaltyBackward", [&] {
      FusedBackward<scalar_t>(p, poses.data_ptr<scalar_t>(), grad_out.data_ptr<scalar_t>(),
                              poses.size(0), grad.data_ptr<scalar_t>());
    });
    return {grad,           torch::Tensor(), torch::Tensor(), torch::Tensor(), torch::Tensor(),
            torch::Tensor()};
  }
};

}  // namespace

void Validate(const AnglePenaltyOptions& o) {
  if (!(o.cos_limit >= 0 && o.cos_limit <= 1)) {
    throw std::invalid_argument("AnglePenaltyOptions.cos_limit = " + std::to_string(o.cos_limit) +
                                " breaks the rule: 0 <= value <= 1");
  }
  Validate(o.degeneracy);
}

AnglePenaltyImpl::AnglePenaltyImpl(const ConstraintSet& set, const AnglePenaltyOptions& options)
    : options_(options), num_joints_(set.num_joints()), num_constraints_(set.num_constraints()) {
  Validate(options_);
  // Registers are laid out level by level: bones first, then crosses whose operands are all in
  // earlier levels. position[r] = where register r lives in the concatenated register tensor.
  const std::vector<VectorOp>& ops = set.ops();
  const int R = static_cast<int>(ops.size());
  std::vector<int> level(R, 0);
  int max_level = 0;
  for (int r = 0; r < R; ++r) {
    if (ops[r].kind == VectorOp::Kind::kCross) {
      level[r] = 1 + std::max(level[ops[r].x], level[ops[r].y]);
      max_level = std::max(max_level, level[r]);
    }
  }
  std::vector<int64_t> position(R, -1);
  int64_t next = 0;
  std::vector<int64_t> from, to;
  for (int r = 0; r < R; ++r) {
    if (level[r] == 0) {
      from.push_back(ops[r].x);
      to.push_back(ops[r].y);
      position[r] = next++;
    }
  }
  bone_from_ = Longs(from);
  bone_to_ = Longs(to);
  for (int l = 1; l <= max_level; ++l) {
    std::vector<int64_t> x, y;
    std::vector<int> members;
    for (int r = 0; r < R; ++r) {
      if (level[r] != l) continue;
      x.push_back(position[ops[r].x]);
      y.push_back(position[ops[r].y]);
      members.push_back(r);
    }
    for (int r : members) position[r] = next++;
    Level lv;
    lv.x = Longs(x);
    lv.y = Longs(y);
    levels_.push_back(lv);
  }
  std::vector<int64_t> a, b;
  std::vector<double> cl, cu, la, ua;
  for (const Constraint& c : set.constraints()) {
    a.push_back(position[c.a]);
    b.push_back(position[c.b]);
    const double lo = std::cos(c.lower_deg * kPi / 180.0);
    const double hi = std::cos(c.upper_deg * kPi / 180.0);
    cl.push_back(lo);
    cu.push_back(hi);
    la.push_back(std::abs(lo) <= options_.cos_limit ? 1.0 : 0.0);
    ua.push_back(std::abs(hi) <= options_.cos_limit ? 1.0 : 0.0);
  }
  a_ = Longs(a);
  b_ = Longs(b);
  std::vector<int64_t> program_ops, program_cons;
  for (const VectorOp& op : ops) {
    program_ops.insert(program_ops.end(), {op.kind == VectorOp::Kind::kBone ? 0 : 1, op.x, op.y});
  }
  std::vector<double> program_bounds;
  for (size_t c = 0; c < set.constraints().size(); ++c) {
    program_cons.insert(program_cons.end(), {set.constraint(c).a, set.constraint(c).b});
    program_bounds.insert(program_bounds.end(), {cl[c], cu[c], la[c], ua[c]});
  }
  program_ops_ = Longs(program_ops).reshape({R, 3});
  program_constraints_ = Longs(program_cons).reshape({num_constraints_, 2});
  program_bounds_ =
      torch::tensor(program_bounds, torch::dtype(torch::kDouble)).reshape({num_constraints_, 4});
  // Double, so double poses see exact bounds; float poses round them as the fused kernel does.
  const auto f = torch::dtype(torch::kDouble);
  cos_lower_ = register_buffer("cos_lower", torch::tensor(cl, f));
  cos_upper_ = register_buffer("cos_upper", torch::tensor(cu, f));
  lower_applied_ = register_buffer("lower_applied", torch::tensor(la, f));
  upper_applied_ = register_buffer("upper_applied", torch::tensor(ua, f));
}

torch::Tensor AnglePenaltyImpl::Cosines(const torch::Tensor& poses, torch::Tensor* defined) const {
  if (poses.dim() < 2 || poses.size(-1) != 3 || poses.size(-2) != num_joints_) {
    throw std::invalid_argument("AnglePenalty: expected poses [..., " +
                                std::to_string(num_joints_) + ", 3], got " +
                                c10::str(poses.sizes()));
  }
  if (!poses.is_floating_point()) {
    throw std::invalid_argument("AnglePenalty: expected floating-point poses, got " +
                                std::string(c10::toString(poses.scalar_type())));
  }
  const torch::Device device = poses.device();
  auto on = [&device](const torch::Tensor& index) {
    return index.device() == device ? index : index.to(device);
  };
  // [..., n_bones, 3]
  torch::Tensor reg = poses.index_select(-2, on(bone_to_)) - poses.index_select(-2, on(bone_from_));
  torch::Tensor len2 = reg.detach().square().sum(-1);  // [..., R so far]
  const double min_len2 =
      double(options_.degeneracy.min_bone_length) * options_.degeneracy.min_bone_length;
  const double min_sin2 =
      double(options_.degeneracy.min_normal_sine) * options_.degeneracy.min_normal_sine;
  torch::Tensor ok = len2 > min_len2;  // [..., R so far] bool, no gradient
  for (const Level& lv : levels_) {
    const torch::Tensor x = on(lv.x), y = on(lv.y);
    const torch::Tensor u = reg.index_select(-2, x);
    const torch::Tensor v = reg.index_select(-2, y);
    const torch::Tensor n = torch::cross(u, v, -1);
    const torch::Tensor n2 = n.detach().square().sum(-1);
    const torch::Tensor level_ok =
        ok.index_select(-1, x) & ok.index_select(-1, y) &
        (n2 > min_sin2 * len2.index_select(-1, x) * len2.index_select(-1, y));
    reg = torch::cat({reg, n}, -2);
    len2 = torch::cat({len2, n2}, -1);
    ok = torch::cat({ok, level_ok}, -1);
  }
  const torch::Tensor a = on(a_), b = on(b_);
  const torch::Tensor va = reg.index_select(-2, a);  // [..., C, 3]
  const torch::Tensor vb = reg.index_select(-2, b);
  const torch::Tensor valid = ok.index_select(-1, a) & ok.index_select(-1, b);  // [..., C]
  // Clamping keeps the division finite (and its gradient zero) for degenerate vectors.
  const double tiny = poses.scalar_type() == torch::kDouble ? 1e-300 : 1e-30;
  const torch::Tensor denom = (va.square().sum(-1) * vb.square().sum(-1)).clamp_min(tiny).sqrt();
  const torch::Tensor cosine = (va * vb).sum(-1) / denom;
  if (defined) *defined = valid;
  return cosine * valid.to(cosine.scalar_type());
}

torch::Tensor AnglePenaltyImpl::PerConstraintComposed(const torch::Tensor& poses) const {
  torch::Tensor valid;
  const torch::Tensor cosine = Cosines(poses, &valid);
  const auto dtype = cosine.scalar_type();
  // Below the lower angle bound = above its cosine, and vice versa.
  const torch::Tensor below =
      torch::relu(cosine - cos_lower_.to(dtype)).square() * lower_applied_.to(dtype);
  const torch::Tensor above =
      torch::relu(cos_upper_.to(dtype) - cosine).square() * upper_applied_.to(dtype);
  return (below + above) * valid.to(dtype);
}

torch::Tensor AnglePenaltyImpl::PerConstraint(const torch::Tensor& poses) const {
  const bool fused =
      options_.fused_cpu && poses.device().is_cpu() &&
      (poses.scalar_type() == torch::kFloat || poses.scalar_type() == torch::kDouble);
  if (!fused) return PerConstraintComposed(poses);
  if (poses.dim() < 2 || poses.size(-1) != 3 || poses.size(-2) != num_joints_) {
    throw std::invalid_argument("AnglePenalty: expected poses [..., " +
                                std::to_string(num_joints_) + ", 3], got " +
                                c10::str(poses.sizes()));
  }
  std::vector<int64_t> out_shape(poses.sizes().begin(), poses.sizes().end() - 2);
  out_shape.push_back(num_constraints_);
  const torch::Tensor flat = poses.reshape({-1, num_joints_, 3}).contiguous();
  const double min_len2 =
      double(options_.degeneracy.min_bone_length) * options_.degeneracy.min_bone_length;
  const double min_sin2 =
      double(options_.degeneracy.min_normal_sine) * options_.degeneracy.min_normal_sine;
  return FusedPenaltyFn::apply(flat, program_ops_, program_constraints_, program_bounds_, min_len2,
                               min_sin2)
      .reshape(out_shape);
}

torch::Tensor AnglePenaltyImpl::forward(const torch::Tensor& poses) const {
  const torch::Tensor per = PerConstraint(poses);
  return per.dim() > 1 ? per.sum(-1).mean() : per.sum();
}

}  // namespace motionfork
