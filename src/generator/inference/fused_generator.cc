#include "generator/inference/fused_generator.h"

#include <torch/torch.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "core/dct.h"
#include "generator/kernels/bf16_product.h"
#include "generator/kernels/panel_product.h"
#include "generator/model/generator_net.h"

namespace motionfork {

namespace {

using kernels::AlignedFloats;
using kernels::PackedWeight;

std::vector<float> ToVector(const torch::Tensor& t) {
  const torch::Tensor c = t.detach().to(torch::kFloat32).contiguous();
  return std::vector<float>(c.data_ptr<float>(), c.data_ptr<float>() + c.numel());
}

PackedWeight Pack(const torch::Tensor& w) {
  const std::vector<float> v = ToVector(w);
  return kernels::PackWeight(v.data(), w.size(0), w.size(1));
}

// One graph-conv layer, eval mode: weights packed, bias and batch norm folded into a scale and a
// shift per (node, feature).
struct Layer {
  PackedWeight weight, shared;         // shared: the latent's weight (input layer only)
  kernels::PackedWeightBf16 weight16;  // the weight in bf16, when the layer's products use it
  bool bf16 = false;

  // z [m, padded] = x [m, K] W in the layer's precision.
  void Product(const float* x, int64_t m, int64_t ldx, float* z) const {
    if (bf16) {
      kernels::MatMulBf16(x, m, ldx, weight16, z);
    } else {
      kernels::MatMul(x, m, ldx, weight, z);
    }
  }
  AlignedFloats adjacency, rowsum, scale, shift;
  bool has_scale = false, tanh = false;

  kernels::LayerEpilogue Epilogue() const {
    kernels::LayerEpilogue e;
    e.nodes = rowsum.size;
    e.adjacency = adjacency.get();
    e.rowsum = rowsum.get();
    e.scale = has_scale ? scale.get() : nullptr;
    e.shift = shift.get();
    e.tanh = tanh;
    return e;
  }
};

Layer MakeLayer(const GraphConvImpl& conv, const NodeBatchNormImpl* norm, bool tanh,
                bool bf16 = false) {
  Layer l;
  l.weight = Pack(conv.weight);
  if (bf16) {
    const std::vector<float> v = ToVector(conv.weight);
    l.weight16 = kernels::PackWeightBf16(v.data(), conv.weight.size(0), conv.weight.size(1));
    l.bf16 = true;
  }
  if (conv.shared_weight.defined()) l.shared = Pack(conv.shared_weight);
  const int64_t N = conv.adjacency.size(0), H = conv.weight.size(1), Hp = l.weight.padded;
  const std::vector<float> a = ToVector(conv.adjacency), bias = ToVector(conv.bias);
  l.adjacency = AlignedFloats(N * N);
  l.rowsum = AlignedFloats(N);
  for (int64_t n = 0; n < N; ++n) {
    double sum = 0;
    for (int64_t m = 0; m < N; ++m) {
      l.adjacency.get()[n * N + m] = a[n * N + m];
      sum += a[n * N + m];
    }
    l.rowsum.get()[n] = static_cast<float>(sum);
  }
  l.scale = AlignedFloats(N * Hp);
  l.shift = AlignedFloats(N * Hp);
  l.tanh = tanh;
  if (norm) {
    l.has_scale = true;
    const torch::Tensor s = norm->gamma * torch::rsqrt(norm->running_var + norm->eps);  // [N, 1, H]
    const std::vector<float> scale = ToVector(s),
                             shift = ToVector(norm->beta - norm->running_mean * s);
    for (int64_t n = 0; n < N; ++n) {
      for (int64_t h = 0; h < H; ++h) {
        l.scale.get()[n * Hp + h] = scale[n * H + h];
        l.shift.get()[n * Hp + h] = bias[h] * scale[n * H + h] + shift[n * H + h];
      }
    }
  } else {
    for (int64_t n = 0; n < N; ++n) std::copy(bias.begin(), bias.end(), l.shift.get() + n * Hp);
  }
  return l;
}

}  // namespace

struct FusedGenerator::Model {
  struct Part {
    Layer input, output;
    std::vector<Layer> hidden;   // two per residual block
    std::vector<int64_t> nodes;  // the joints this part overwrites
  };
  int64_t N = 0, C = 0, H = 0, Hp = 0, nz = 0, n_pre = 0, t_his = 0, t_pred = 0;
  std::vector<float> dct;  // [n_pre, t_his + t_pred]
  PackedWeight idct;       // the future frames' columns of the inverse DCT: [n_pre, t_pred]
  std::vector<Part> parts;

  // Scratch of one Predict call.
  // Scratch of one Predict call, carved from a buffer each thread keeps between calls (so that
  // calls do not pay for fresh pages); every value is written before it is read.
  struct Work {
    float *cur, *h0, *h1, *z, *q;
    Work(const Model& m, int64_t samples) {
      const int64_t sizes[] = {samples * m.N * m.C, samples * m.N * m.H, samples * m.N * m.H,
                               samples * m.N * std::max({m.Hp, 3 * m.idct.padded, m.C + 15}),
                               samples * m.Hp};
      int64_t total = 0;
      for (int64_t size : sizes) total += (size + 15) / 16 * 16;
      thread_local AlignedFloats arena;
      if (arena.size < total) arena = AlignedFloats(total, /*zero=*/false);
      float* next = arena.get();
      float** slots[] = {&cur, &h0, &h1, &z, &q};
      for (int i = 0; i < 5; ++i) {
        *slots[i] = next;
        next += (sizes[i] + 15) / 16 * 16;
      }
    }
  };

  // out = layer(x) (+ residual) for a hidden layer, [samples, N, H]. The product rows of a few
  // samples at a time, so that they are still in the L1 cache when mixed.
  void HiddenLayer(const Layer& layer, const float* x, int64_t samples, const float* residual,
                   float* out, Work& w) const;

  // Runs part p on `samples` samples of cur [samples, N, C] (updated in place, own nodes only).
  // group > 1: the samples come in groups of `group` sharing the same input rows.
  void RunPart(const Part& part, float* cur, int64_t samples, const float* z, int64_t group,
               Work& w) const;
};

namespace {

// The fused path sizes its buffers from the network's own tensors: a layer of another size than
// the first one's (a network whose weights disagree with its options) is refused, not run.
void RequireShape(const torch::Tensor& t, const std::vector<int64_t>& expected, const char* what) {
  if (t.sizes().vec() == expected) return;
  std::string e, f;
  for (int64_t v : expected) e += (e.empty() ? "" : ", ") + std::to_string(v);
  for (int64_t v : t.sizes()) f += (f.empty() ? "" : ", ") + std::to_string(v);
  throw std::invalid_argument(std::string("fused generator: ") + what + " has shape [" + f +
                              "], expected [" + e + "]");
}

void RequireLayer(const GraphConvImpl& conv, int64_t N, int64_t in, int64_t out, const char* what) {
  RequireShape(conv.adjacency, {N, N}, what);
  RequireShape(conv.weight, {in, out}, what);
}

}  // namespace

FusedGenerator::FusedGenerator(const GeneratorNetImpl& net, ProductPrecision precision,
                               const std::vector<bool>& bf16_layers)
    : model_(std::make_unique<Model>()) {
  size_t hidden_index = 0;  // over all parts, for bf16_layers
  const bool bf16 = precision == ProductPrecision::kBf16;
  Model& m = *model_;
  const GeneratorOptions& o = net.options();
  m.N = o.num_nodes;
  m.C = o.coeff_features();
  m.H = net.num_parts() > 0 ? net.part(0)->input->conv->weight.size(1) : o.hidden;
  m.nz = o.nz;
  m.n_pre = o.n_pre;
  m.t_his = o.t_his;
  m.t_pred = o.t_pred;
  const int64_t T = o.num_frames();
  const Eigen::MatrixXd d = DctMatrix(static_cast<int>(T)).topRows(o.n_pre);
  m.dct.resize(static_cast<size_t>(o.n_pre * T));
  std::vector<float> idct(static_cast<size_t>(o.n_pre * o.t_pred));
  for (int64_t l = 0; l < o.n_pre; ++l) {
    for (int64_t t = 0; t < T; ++t) {
      m.dct[l * T + t] = static_cast<float>(d(l, t));
      if (t >= o.t_his) idct[l * o.t_pred + t - o.t_his] = static_cast<float>(d(l, t));
    }
  }
  m.idct = kernels::PackWeight(idct.data(), o.n_pre, o.t_pred);
  for (int64_t p = 0; p < net.num_parts(); ++p) {
    const PartNetworkImpl& pn = *net.part(p);
    Model::Part part;
    RequireShape(pn.input->conv->adjacency, {m.N, m.N}, "an input layer's adjacency");
    RequireShape(pn.input->conv->weight, {pn.input->conv->weight.size(0), m.H}, "an input layer");
    part.input = MakeLayer(*pn.input->conv, pn.input->norm ? pn.input->norm.get() : nullptr, true);
    // Without a choice, bf16 in the later half of the part's hidden layers (see ProductPrecision).
    const size_t hidden_layers = 2 * pn.blocks->size();
    for (const auto& module : *pn.blocks) {
      const auto* block = module->as<ResidualBlockImpl>();
      for (const GraphLayer& layer : {block->first, block->second}) {
        RequireLayer(*layer->conv, m.N, m.H, m.H, "a hidden layer");
        const bool chosen = bf16_layers.empty()
                                ? 2 * part.hidden.size() >= hidden_layers
                                : hidden_index < bf16_layers.size() && bf16_layers[hidden_index];
        ++hidden_index;
        part.hidden.push_back(MakeLayer(*layer->conv, layer->norm ? layer->norm.get() : nullptr,
                                        true, bf16 && chosen));
      }
    }
    RequireLayer(*pn.output, m.N, m.H, m.C, "an output layer");
    part.output = MakeLayer(*pn.output, nullptr, false);
    part.nodes = net.part_nodes()[p];
    m.parts.push_back(std::move(part));
  }
  m.Hp = (m.H + 15) / 16 * 16;
}

FusedGenerator::~FusedGenerator() = default;
FusedGenerator::FusedGenerator(FusedGenerator&&) noexcept = default;
FusedGenerator& FusedGenerator::operator=(FusedGenerator&&) noexcept = default;

void FusedGenerator::Model::HiddenLayer(const Layer& layer, const float* x, int64_t samples,
                                        const float* residual, float* out, Work& w) const {
  const kernels::LayerEpilogue e = layer.Epilogue();
  const int64_t chunk = std::max<int64_t>(1, 48 / N);  // about 48 rows: 48 KB of products
  for (int64_t s0 = 0; s0 < samples; s0 += chunk) {
    const int64_t count = std::min(chunk, samples - s0);
    layer.Product(x + s0 * N * H, count * N, H, w.z);
    for (int64_t b = 0; b < count; ++b) {
      const int64_t offset = (s0 + b) * N * H;
      kernels::MixRows(e, w.z + b * N * Hp, Hp, H, nullptr, nullptr, N,
                       residual ? residual + offset : nullptr, out + offset, H);
    }
  }
}

void FusedGenerator::Model::RunPart(const Part& part, float* cur, int64_t samples, const float* z,
                                    int64_t group, Work& w) const {
  const int64_t rows = N * Hp;
  // Input layer: A (X W_x + 1 z W_z) + b, X W_x once per group of samples sharing their input.
  const kernels::LayerEpilogue in = part.input.Epilogue();
  for (int64_t g = 0; g < samples / group; ++g) {
    kernels::MatMul(cur + g * group * N * C, N, C, part.input.weight, w.z + g * rows);
  }
  kernels::MatMul(z, samples, nz, part.input.shared, w.q);
  for (int64_t b = 0; b < samples; ++b) {
    kernels::MixRows(in, w.z + (b / group) * rows, Hp, H, w.q + b * Hp, nullptr, N, nullptr,
                     w.h0 + b * N * H, H);
  }
  // Residual blocks: h1 = layer(h0); h0 = layer(h1) + h0.
  for (size_t i = 0; i + 1 < part.hidden.size(); i += 2) {
    HiddenLayer(part.hidden[i], w.h0, samples, nullptr, w.h1, w);
    HiddenLayer(part.hidden[i + 1], w.h1, samples, w.h0, w.h0, w);
  }
  // Output layer, own nodes only: coefficients += A (h W) + b.
  const kernels::LayerEpilogue out = part.output.Epilogue();
  const int64_t Cp = part.output.weight.padded;
  part.output.Product(w.h0, samples * N, H, w.z);
  for (int64_t b = 0; b < samples; ++b) {
    float* c = cur + b * N * C;
    kernels::MixRows(out, w.z + b * N * Cp, Cp, C, nullptr, part.nodes.data(),
                     static_cast<int64_t>(part.nodes.size()), c, c, C);
  }
}

void FusedGenerator::Predict(const float* histories, int64_t num_histories, int64_t k,
                             const std::vector<const float*>& z, const std::vector<bool>& fixed,
                             float* futures) const {
  const Model& m = *model_;
  if (z.size() != m.parts.size()) {
    throw std::invalid_argument("generator: expected " + std::to_string(m.parts.size()) +
                                " latents (one per part), got " + std::to_string(z.size()));
  }
  const int64_t N = m.N, C = m.C, B = num_histories * k, T = m.t_his + m.t_pred;
  Model::Work w(m, B);
  // DCT of each history padded with its last frame, written to its k samples: cur [B, N, C],
  // C = (axis, coefficient).
  std::vector<float> coeffs(static_cast<size_t>(N * C));
  for (int64_t h = 0; h < num_histories; ++h) {
    const float* x = histories + h * m.t_his * N * 3;
    std::fill(coeffs.begin(), coeffs.end(), 0.0f);
    for (int64_t t = 0; t < T; ++t) {
      const float* frame = x + std::min(t, m.t_his - 1) * N * 3;
      for (int64_t l = 0; l < m.n_pre; ++l) {
        const float d = m.dct[l * T + t];
        for (int64_t n = 0; n < N; ++n)
          for (int64_t a = 0; a < 3; ++a) coeffs[n * C + a * m.n_pre + l] += d * frame[n * 3 + a];
      }
    }
    for (int64_t j = 0; j < k; ++j)
      std::copy(coeffs.begin(), coeffs.end(), w.cur + (h * k + j) * N * C);
  }
  // The parts in order; a fixed part runs on each history's first sample and is copied to the rest.
  bool varied = false;
  for (size_t p = 0; p < m.parts.size(); ++p) {
    const bool is_fixed = p < fixed.size() && fixed[p];
    if (is_fixed && k > 1) {
      AlignedFloats first(num_histories * N * C), zf(num_histories * m.nz);
      for (int64_t h = 0; h < num_histories; ++h) {
        std::memcpy(first.get() + h * N * C, w.cur + h * k * N * C, sizeof(float) * N * C);
        std::memcpy(zf.get() + h * m.nz, z[p] + h * k * m.nz, sizeof(float) * m.nz);
      }
      m.RunPart(m.parts[p], first.get(), num_histories, zf.get(), 1, w);
      for (int64_t b = 0; b < B; ++b) {
        for (int64_t n : m.parts[p].nodes) {
          std::memcpy(w.cur + (b * N + n) * C, first.get() + ((b / k) * N + n) * C,
                      sizeof(float) * C);
        }
      }
    } else {
      m.RunPart(m.parts[p], w.cur, B, z[p], varied ? 1 : k, w);
    }
    varied = varied || !is_fixed;
  }
  // Inverse DCT of the future frames: rows (sample, node, axis) x [n_pre, t_pred], then
  // transposed to [B, t_pred, N, 3].
  const int64_t Tp = m.idct.padded;
  kernels::MatMul(w.cur, B * N * 3, m.n_pre, m.idct, w.z);
  for (int64_t b = 0; b < B; ++b) {
    const float* src = w.z + b * N * 3 * Tp;
    float* dst = futures + b * m.t_pred * N * 3;
    for (int64_t na = 0; na < N * 3; ++na)
      for (int64_t t = 0; t < m.t_pred; ++t) dst[t * N * 3 + na] = src[na * Tp + t];
  }
}

}  // namespace motionfork
