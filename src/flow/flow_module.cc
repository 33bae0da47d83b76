#include "flow/flow_module.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace motionfork {
namespace {

constexpr double kLog2Pi = 1.8378770664093454835606594728112;

torch::TensorOptions F64() { return torch::TensorOptions().dtype(torch::kFloat64); }

}  // namespace

InvertibleLinearImpl::InvertibleLinearImpl(int dim, int num_reflections)
    : dim_(dim), num_reflections_(num_reflections) {
  if (dim < 1)
    throw std::invalid_argument("InvertibleLinear: expected dim >= 1, got " + std::to_string(dim));
  if (num_reflections < 1 || num_reflections > dim) {
    throw std::invalid_argument("InvertibleLinear: expected 1.." + std::to_string(dim) +
                                " reflections, got " + std::to_string(num_reflections));
  }
  reflections = register_parameter("reflections", torch::zeros({num_reflections, dim}));
  r_log_diag = register_parameter("r_log_diag", torch::zeros({dim}));
  r_upper = register_parameter("r_upper", torch::zeros({int64_t(dim) * (dim - 1) / 2}));
  bias = register_parameter("bias", torch::zeros({dim}));
  const torch::Tensor idx = torch::triu_indices(dim, dim, 1);  // [2, D (D - 1) / 2], row-major
  upper_rows_ = idx[0].clone();
  upper_cols_ = idx[1].clone();
}

torch::Tensor InvertibleLinearImpl::Orthogonal() const {
  // Householder vectors u_k (unit rows of U^T): H_k = I - 2 u_k u_k^T and
  // H_1 ... H_K = I - U T^-1 U^T with T = striu(U^T U) + I / 2 (Joffrain et al., "Accumulating
  // Householder transformations, revisited", 2006).
  const torch::Tensor v = reflections.to(torch::kFloat64);
  const torch::Tensor u = v / v.norm(2, 1, true).clamp_min(1e-150);  // [K, D]
  const torch::Tensor gram = u.mm(u.t());                            // [K, K]
  const torch::Tensor t = gram.triu(1) + 0.5 * torch::eye(num_reflections_, F64());
  const torch::Tensor x = torch::linalg_solve_triangular(t, u, /*upper=*/true);  // T^-1 U^T
  return torch::eye(dim_, F64()) - u.t().mm(x);
}

torch::Tensor InvertibleLinearImpl::OrthogonalSequential() const {
  const torch::Tensor v = reflections.to(torch::kFloat64);
  torch::Tensor q = torch::eye(dim_, F64());
  for (int k = 0; k < num_reflections_; ++k) {
    const torch::Tensor u = (v[k] / v[k].norm()).unsqueeze(1);  // [D, 1]
    q = q - 2.0 * q.mm(u).mm(u.t());
  }
  return q;
}

torch::Tensor InvertibleLinearImpl::Triangular() const {
  const torch::Tensor strict =
      torch::zeros({dim_, dim_}, F64())
          .index_put({upper_rows_, upper_cols_}, r_upper.to(torch::kFloat64));
  return strict + torch::diag(r_log_diag.to(torch::kFloat64).exp());
}

torch::Tensor InvertibleLinearImpl::Weight() const { return Orthogonal().mm(Triangular()); }

torch::Tensor InvertibleLinearImpl::InverseWeight() const {
  const torch::Tensor r_inv =
      torch::linalg_solve_triangular(Triangular(), torch::eye(dim_, F64()), /*upper=*/true);
  return r_inv.mm(Orthogonal().t());
}

torch::Tensor InvertibleLinearImpl::LogAbsDet() const {
  return r_log_diag.to(torch::kFloat64).sum();
}

PoseFlowImpl::PoseFlowImpl(int dim, const FlowOptions& options) : dim_(dim), options_(options) {
  PriorConfig check;
  check.model = options;
  ValidatePriorConfig(check);
  if (dim < 1)
    throw std::invalid_argument("PoseFlow: expected dim >= 1, got " + std::to_string(dim));
  const int k = options.num_reflections == 0 ? dim : options.num_reflections;
  if (k > dim) {
    throw std::invalid_argument("model.reflections = " + std::to_string(k) +
                                " breaks the rule: must be <= dim (" + std::to_string(dim) + ")");
  }
  options_.num_reflections = k;
  for (int l = 0; l < options.num_layers; ++l) {
    layers_.push_back(register_module("layer" + std::to_string(l), InvertibleLinear(dim, k)));
    if (l + 1 < options.num_layers) {
      prelu_log_slopes_.push_back(
          register_parameter("prelu" + std::to_string(l) + "_log_slope",
                             torch::full({1}, std::log(options.prelu_init))));
    }
  }
}

void PoseFlowImpl::Initialize(uint64_t seed) {
  torch::NoGradGuard no_grad;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double bound = 1.0 / std::sqrt(static_cast<double>(dim_));
  std::uniform_real_distribution<double> uniform(-bound, bound);
  auto fill = [](torch::Tensor& t, auto&& draw) {
    std::vector<float> values(static_cast<size_t>(t.numel()));
    for (float& v : values) v = static_cast<float>(draw());
    t.copy_(torch::from_blob(values.data(), t.sizes(), torch::kFloat32).to(t.dtype()));
  };
  for (auto& layer : layers_) {
    fill(layer->reflections, [&] { return normal(rng); });
    fill(layer->r_log_diag, [&] { return uniform(rng); });
    fill(layer->r_upper, [&] { return uniform(rng); });
    fill(layer->bias, [&] { return uniform(rng); });
  }
  for (auto& a : prelu_log_slopes_) a.fill_(std::log(options_.prelu_init));
}

void PoseFlowImpl::CheckInput(const torch::Tensor& x, const char* what) const {
  if (x.dim() != 2 || x.size(1) != dim_) {
    throw std::invalid_argument(std::string("PoseFlow: expected ") + what + " [B, " +
                                std::to_string(dim_) + "], got " + c10::str(x.sizes()));
  }
  if (!x.is_floating_point()) {
    throw std::invalid_argument(std::string("PoseFlow: expected floating-point ") + what +
                                ", got " + c10::toString(x.scalar_type()));
  }
}

PoseFlowImpl::Pass PoseFlowImpl::Run(const torch::Tensor& x) const {
  const auto dtype = x.scalar_type();
  torch::Tensor constant = torch::zeros({}, F64());  // sum of the layers' log |det W|
  torch::Tensor prelu_terms;                         // [B]
  Pass pass;
  torch::Tensor y = x;
  for (size_t l = 0; l < layers_.size(); ++l) {
    const InvertibleLinear& layer = layers_[l];
    y = torch::addmm(layer->bias.to(dtype), y, layer->Weight().to(dtype));
    constant = constant + layer->LogAbsDet();
    if (l + 1 < layers_.size()) {
      // PReLU as y * (n slope + (1 - n)), n = 1 where y < 0 (the factor is exactly slope or 1):
      // a cheaper backward than torch::prelu's (which always reduces the slope's gradient), and
      // n is what the log-det counts. (torch::where with 0-d operands is ~30x slower here.)
      const torch::Tensor negative = y.lt(0);
      const torch::Tensor n = negative.to(dtype);
      const torch::Tensor alpha = prelu_log_slopes_[l].to(dtype).squeeze();
      const torch::Tensor term = n.sum(1) * alpha;
      prelu_terms = prelu_terms.defined() ? prelu_terms + term : term;
      y = y * (n * alpha.exp() + (1 - n));
      pass.negative.push_back(negative);
    }
  }
  pass.z = y;
  pass.log_det = prelu_terms.defined() ? prelu_terms + constant.to(dtype)
                                       : constant.to(dtype).expand({x.size(0)}).clone();
  return pass;
}

namespace {

// log_prob with the gradient to the poses only, for a frozen prior inside another network's
// training graph: saves z and the PReLU masks (1 byte per number) instead of every intermediate,
// and back-propagates with one product per layer:
//   d log p / dx = -J^T z,  J^T g = W_1 S_1 ... W_L g  (S_l = diag(PReLU slopes)).
class FrozenLogProb : public torch::autograd::Function<FrozenLogProb> {
 public:
  static torch::Tensor forward(torch::autograd::AutogradContext* ctx, const torch::Tensor& x,
                               const PoseFlowImpl* flow) {
    const PoseFlowImpl::Pass pass = flow->Run(x);
    std::vector<torch::Tensor> saved = {pass.z};
    saved.insert(saved.end(), pass.negative.begin(), pass.negative.end());
    ctx->save_for_backward(saved);
    std::vector<torch::Tensor> weights_t, slopes;
    for (int l = 0; l < flow->num_layers(); ++l) {
      weights_t.push_back(flow->layer(l)->Weight().to(x.scalar_type()).t().contiguous());
      if (l + 1 < flow->num_layers()) {
        slopes.push_back(flow->prelu_log_slope(l).to(x.scalar_type()).squeeze().exp());
      }
    }
    ctx->saved_data["weights_t"] = weights_t;
    ctx->saved_data["slopes"] = slopes;
    return pass.log_det - 0.5 * pass.z.square().sum(1) - 0.5 * kLog2Pi * x.size(1);
  }

  static torch::autograd::variable_list backward(torch::autograd::AutogradContext* ctx,
                                                 torch::autograd::variable_list grad) {
    const auto saved = ctx->get_saved_variables();
    const auto weights_t = ctx->saved_data["weights_t"].toTensorVector();
    const auto slopes = ctx->saved_data["slopes"].toTensorVector();
    const torch::Tensor& z = saved[0];
    torch::Tensor g = z * (-grad[0]).unsqueeze(1);
    for (int l = static_cast<int>(weights_t.size()) - 1; l >= 0; --l) {
      if (l + 1 < static_cast<int>(weights_t.size())) {
        const torch::Tensor n = saved[1 + l].to(g.scalar_type());
        g = g * (n * slopes[l] + (1 - n));
      }
      g = g.mm(weights_t[l]);
    }
    return {g, torch::Tensor()};
  }
};

}  // namespace

std::pair<torch::Tensor, torch::Tensor> PoseFlowImpl::forward(const torch::Tensor& x) const {
  CheckInput(x, "poses");
  Pass pass = Run(x);
  return {pass.z, pass.log_det};
}

torch::Tensor PoseFlowImpl::inverse(const torch::Tensor& z) const {
  CheckInput(z, "latents");
  const auto dtype = z.scalar_type();
  torch::Tensor x = z;
  for (int l = static_cast<int>(layers_.size()) - 1; l >= 0; --l) {
    if (l + 1 < static_cast<int>(layers_.size())) {
      // A PReLU with slope a > 0 keeps signs, so its inverse is a PReLU with slope 1 / a.
      const torch::Tensor inv_slope = (-prelu_log_slopes_[l]).to(dtype).squeeze().exp();
      const torch::Tensor n = x.lt(0).to(dtype);
      x = x * (n * inv_slope + (1 - n));
    }
    const InvertibleLinear& layer = layers_[l];
    x = (x - layer->bias.to(dtype)).mm(layer->InverseWeight().to(dtype));
  }
  return x;
}

bool PoseFlowImpl::AnyParameterRequiresGrad() const {
  for (const auto& p : OrderedParameters()) {
    if (p.second.requires_grad()) return true;
  }
  return false;
}

void PoseFlowImpl::Freeze() {
  for (auto& p : parameters()) p.requires_grad_(false);
  eval();
}

torch::Tensor PoseFlowImpl::log_prob(const torch::Tensor& x) const {
  CheckInput(x, "poses");
  if (torch::GradMode::is_enabled() && x.requires_grad() && !AnyParameterRequiresGrad()) {
    return FrozenLogProb::apply(x, this);
  }
  const Pass pass = Run(x);
  return pass.log_det - 0.5 * pass.z.square().sum(1) - 0.5 * kLog2Pi * dim_;
}

std::vector<std::pair<std::string, torch::Tensor>> PoseFlowImpl::OrderedParameters() const {
  std::vector<std::pair<std::string, torch::Tensor>> out;
  for (size_t l = 0; l < layers_.size(); ++l) {
    const std::string p = "layer" + std::to_string(l) + ".";
    out.emplace_back(p + "reflections", layers_[l]->reflections);
    out.emplace_back(p + "r_log_diag", layers_[l]->r_log_diag);
    out.emplace_back(p + "r_upper", layers_[l]->r_upper);
    out.emplace_back(p + "bias", layers_[l]->bias);
    if (l < prelu_log_slopes_.size()) {
      out.emplace_back("prelu" + std::to_string(l) + "_log_slope", prelu_log_slopes_[l]);
    }
  }
  return out;
}

int64_t PoseFlowImpl::NumParameters() const {
  int64_t n = 0;
  for (const auto& p : OrderedParameters()) n += p.second.numel();
  return n;
}

namespace {

void CheckPositions(const torch::Tensor& positions, const std::vector<int>& parents,
                    bool implicit_root) {
  const int64_t J = static_cast<int64_t>(parents.size());
  const int64_t stored = implicit_root ? J - 1 : J;
  if (J < 2 || positions.dim() < 2 || positions.size(-1) != 3 || positions.size(-2) != stored) {
    throw std::invalid_argument(
        std::string(implicit_root ? "LimbDirectionsRootRelative" : "LimbDirections") +
        ": expected positions [..., " + std::to_string(stored) + ", 3] for " + std::to_string(J) +
        " joints" + (implicit_root ? " (root omitted)" : "") + ", got " +
        c10::str(positions.sizes()));
  }
  for (int64_t j = 1; j < J; ++j) {
    if (parents[j] < 0 || parents[j] >= j) {
      throw std::invalid_argument("LimbDirections: expected parents[j] in [0, j) for j >= 1, got " +
                                  std::to_string(parents[j]) + " for joint " + std::to_string(j));
    }
  }
}

// Tensor ops: any device and dtype, autograd through every op.
torch::Tensor LimbDirectionsOps(const torch::Tensor& positions, const std::vector<int>& parents,
                                double eps, bool implicit_root) {
  torch::Tensor pos = positions;
  if (implicit_root) {
    std::vector<int64_t> root_shape = positions.sizes().vec();
    root_shape[root_shape.size() - 2] = 1;
    pos = torch::cat({torch::zeros(root_shape, positions.options()), positions}, -2);
  }
  std::vector<int64_t> child_idx, parent_idx;
  for (size_t j = 1; j < parents.size(); ++j) {
    child_idx.push_back(static_cast<int64_t>(j));
    parent_idx.push_back(parents[j]);
  }
  const auto opts = torch::TensorOptions().dtype(torch::kInt64).device(pos.device());
  const torch::Tensor v = pos.index_select(-2, torch::tensor(child_idx, opts)) -
                          pos.index_select(-2, torch::tensor(parent_idx, opts));
  const torch::Tensor n = (v.square().sum(-1, true) + eps * eps).sqrt();
  return (v / n).flatten(-2);
}

// CPU float/double: one pass each way. d = v / n with n = sqrt(|v|^2 + eps^2), v = joint - parent;
// backward: dL/dv = (g - d (d . g)) / n, added to the joint and subtracted from its parent. With
// implicit_root the positions omit joint 0, which sits at the origin.
class LimbDirectionsCpu : public torch::autograd::Function<LimbDirectionsCpu> {
 public:
  static torch::Tensor forward(torch::autograd::AutogradContext* ctx,
                               const torch::Tensor& positions, const std::vector<int>& parents,
                               double eps, bool implicit_root) {
    const torch::Tensor pos = positions.contiguous();
    const int64_t J = static_cast<int64_t>(parents.size()), L = J - 1;
    const int64_t S = implicit_root ? J - 1 : J;  // joints stored per pose
    const int64_t shift = implicit_root ? 1 : 0;  // joint j is stored at j - shift
    const int64_t B = pos.numel() / (S * 3);
    std::vector<int64_t> out_shape(pos.sizes().begin(), pos.sizes().end() - 2);
    out_shape.push_back(3 * L);
    torch::Tensor dirs = torch::empty(out_shape, pos.options());
    torch::Tensor inv = torch::empty({B, L}, pos.options());
    AT_DISPATCH_FLOATING_TYPES(pos.scalar_type(), "LimbDirections", [&] {
      const scalar_t* p = pos.data_ptr<scalar_t>();
      scalar_t* d = dirs.data_ptr<scalar_t>();
      scalar_t* r = inv.data_ptr<scalar_t>();
      const scalar_t eps2 = static_cast<scalar_t>(eps * eps);
      const scalar_t origin[3] = {0, 0, 0};
      at::parallel_for(0, B, 2048, [&](int64_t begin, int64_t end) {
        for (int64_t b = begin; b < end; ++b) {
          const scalar_t* pb = p + b * S * 3;
          for (int64_t k = 0; k < L; ++k) {
            const int64_t par = parents[k + 1];
            const scalar_t* c = pb + (k + 1 - shift) * 3;
            const scalar_t* q = par < shift ? origin : pb + (par - shift) * 3;
            const scalar_t v0 = c[0] - q[0], v1 = c[1] - q[1], v2 = c[2] - q[2];
            const scalar_t rk = 1 / std::sqrt(v0 * v0 + v1 * v1 + v2 * v2 + eps2);
            scalar_t* dk = d + (b * L + k) * 3;
            dk[0] = v0 * rk, dk[1] = v1 * rk, dk[2] = v2 * rk;
            r[b * L + k] = rk;
          }
        }
      });
    });
    ctx->save_for_backward({dirs, inv});
    ctx->saved_data["parents"] = std::vector<int64_t>(parents.begin(), parents.end());
    ctx->saved_data["shape"] = pos.sizes().vec();
    ctx->saved_data["shift"] = shift;
    return dirs;
  }

  static torch::autograd::variable_list backward(torch::autograd::AutogradContext* ctx,
                                                 torch::autograd::variable_list grad) {
    const auto saved = ctx->get_saved_variables();
    const torch::Tensor& dirs = saved[0];
    const torch::Tensor& inv = saved[1];
    const std::vector<int64_t> parents = ctx->saved_data["parents"].toIntVector();
    const std::vector<int64_t> shape = ctx->saved_data["shape"].toIntVector();
    const int64_t shift = ctx->saved_data["shift"].toInt();
    const torch::Tensor g = grad[0].to(dirs.scalar_type()).contiguous();
    const int64_t J = static_cast<int64_t>(parents.size()), L = J - 1, S = J - shift;
    const int64_t B = inv.size(0);
    torch::Tensor out = torch::zeros(shape, dirs.options());
    AT_DISPATCH_FLOATING_TYPES(dirs.scalar_type(), "LimbDirectionsBackward", [&] {
      const scalar_t* d = dirs.data_ptr<scalar_t>();
      const scalar_t* r = inv.data_ptr<scalar_t>();
      const scalar_t* gd = g.data_ptr<scalar_t>();
      scalar_t* gp = out.data_ptr<scalar_t>();
      at::parallel_for(0, B, 2048, [&](int64_t begin, int64_t end) {
        scalar_t sink[3];  // the implicit root's gradient is dropped
        for (int64_t b = begin; b < end; ++b) {
          scalar_t* gb = gp + b * S * 3;
          for (int64_t k = 0; k < L; ++k) {
            const scalar_t* dk = d + (b * L + k) * 3;
            const scalar_t* gk = gd + (b * L + k) * 3;
            const scalar_t dot = dk[0] * gk[0] + dk[1] * gk[1] + dk[2] * gk[2];
            const scalar_t rk = r[b * L + k];
            const int64_t par = parents[k + 1];
            scalar_t* c = gb + (k + 1 - shift) * 3;
            scalar_t* q = par < shift ? sink : gb + (par - shift) * 3;
            for (int a = 0; a < 3; ++a) {
              const scalar_t gv = (gk[a] - dk[a] * dot) * rk;
              c[a] += gv;
              q[a] -= gv;
            }
          }
        }
      });
    });
    return {out, torch::Tensor(), torch::Tensor(), torch::Tensor()};
  }
};

torch::Tensor LimbDirectionsImpl(const torch::Tensor& positions, const std::vector<int>& parents,
                                 double eps, bool implicit_root) {
  CheckPositions(positions, parents, implicit_root);
  const auto type = positions.scalar_type();
  if (positions.is_cpu() && (type == torch::kFloat32 || type == torch::kFloat64)) {
    return LimbDirectionsCpu::apply(positions, parents, eps, implicit_root);
  }
  return LimbDirectionsOps(positions, parents, eps, implicit_root);
}

}  // namespace

torch::Tensor LimbDirections(const torch::Tensor& positions, const std::vector<int>& parents,
                             double eps) {
  return LimbDirectionsImpl(positions, parents, eps, false);
}

torch::Tensor LimbDirectionsRootRelative(const torch::Tensor& poses,
                                         const std::vector<int>& parents, double eps) {
  return LimbDirectionsImpl(poses, parents, eps, true);
}

torch::Tensor LimbDirectionsReference(const torch::Tensor& positions,
                                      const std::vector<int>& parents, double eps) {
  CheckPositions(positions, parents, false);
  return LimbDirectionsOps(positions, parents, eps, false);
}

}  // namespace motionfork
