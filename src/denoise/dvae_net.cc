#include "denoise/dvae_net.h"

#include <cmath>

namespace motionfork {

namespace {

constexpr double kLogVarMin = -12, kLogVarMax = 6;

torch::Tensor Noise(const torch::Tensor& like, c10::optional<at::Generator> gen) {
  return at::normal(0.0, 1.0, like.sizes(), gen, like.options());
}

}  // namespace

DvaeMlpImpl::DvaeMlpImpl(int64_t in, int64_t hidden, int64_t out, int64_t groups) {
  l1 = register_module("l1", torch::nn::Linear(in, hidden));
  g1 = register_module("g1", torch::nn::GroupNorm(groups, hidden));
  l2 = register_module("l2", torch::nn::Linear(hidden, hidden));
  g2 = register_module("g2", torch::nn::GroupNorm(groups, hidden));
  l3 = register_module("l3", torch::nn::Linear(hidden, out));
}

torch::Tensor DvaeMlpImpl::forward(const torch::Tensor& x) {
  auto shape = x.sizes().vec();
  torch::Tensor h = x.reshape({-1, shape.back()});
  h = torch::relu(g1(l1(h)));
  h = torch::relu(g2(l2(h)));
  h = l3(h);
  shape.back() = h.size(1);
  return h.reshape(shape);
}

DvaeNetImpl::DvaeNetImpl(const DvaeOptions& o, int64_t values, const RefinerOptions& refine)
    : options_(o), values_(values) {
  const int64_t H = o.hidden, Z = o.latent, M = o.mlp_hidden, G = o.groups, F = values;
  d_ini = register_module("d_ini", DvaeMlp(F, M, H, G));
  d_x = register_module("d_x", DvaeMlp(H, M, F, G));
  d_z = register_module("d_z", DvaeMlp(H, M, 2 * Z, G));
  dec_lstm =
      register_module("dec_lstm", torch::nn::LSTM(torch::nn::LSTMOptions(Z, H).batch_first(true)));
  e_ini = register_module("e_ini", DvaeMlp(F, M, H, G));
  e_glob = register_module("e_glob", DvaeMlp(2 * H, M, 2 * Z, G));
  e_data =
      register_module("e_data", torch::nn::LSTM(torch::nn::LSTMOptions(F, H).batch_first(true)));
  e_lat = register_module("e_lat", torch::nn::LSTMCell(torch::nn::LSTMCellOptions(Z, H)));
  r_h = register_module("r_h", torch::nn::LSTM(torch::nn::LSTMOptions(F, H).batch_first(true)));
  e_x0 = register_module("e_x0", DvaeMlp(H, M, 2 * F, G));
  e_b = register_module("e_b", DvaeMlp(H + 2 * F, M, 2 * F, G));
  x_logvar = register_parameter("x_logvar", torch::full({F}, -2.0));
  if (refine.enabled()) refiner = register_module("refiner", TemporalRefiner(refine, F, F));
}

DvaePass DvaeNetImpl::Run(const torch::Tensor& seq, const torch::Tensor& x0, bool sample,
                          c10::optional<at::Generator> gen) {
  const int64_t B = seq.size(0), T = seq.size(1) - 1, H = options_.hidden;
  DvaePass p;
  p.x0 = x0;
  // Backward recurrence over the data: h^data_t summarises x_t..x_T.
  const torch::Tensor data = seq.slice(1, 1);
  const torch::Tensor h_data = std::get<0>(e_data->forward(data.flip(1))).flip(1);  // [B, T, H]
  torch::Tensor hl = e_ini(x0), cl = torch::zeros({B, H}, seq.options());
  std::vector<torch::Tensor> zs, means, logvars;
  for (int64_t t = 0; t < T; ++t) {
    const auto q = e_glob(torch::cat({hl, h_data.select(1, t)}, 1)).chunk(2, 1);
    const torch::Tensor lv = q[1].clamp(kLogVarMin, kLogVarMax);
    torch::Tensor z = q[0];
    if (sample) z = z + torch::exp(0.5 * lv) * Noise(z, gen);
    std::tie(hl, cl) = e_lat(z, std::make_tuple(hl, cl));
    zs.push_back(z);
    means.push_back(q[0]);
    logvars.push_back(lv);
  }
  p.z = torch::stack(zs, 1);
  p.post_mean = torch::stack(means, 1);
  p.post_logvar = torch::stack(logvars, 1);
  const torch::Tensor h0 = d_ini(x0);
  const torch::Tensor out = std::get<0>(
      dec_lstm->forward(p.z, std::make_tuple(h0.unsqueeze(0), torch::zeros_like(h0).unsqueeze(0))));
  p.hidden = torch::cat({h0.unsqueeze(1), out}, 1);
  const auto prior = d_z(p.hidden.slice(1, 0, T)).chunk(2, 2);
  p.prior_mean = prior[0];
  p.prior_logvar = prior[1].clamp(kLogVarMin, kLogVarMax);
  p.mean = d_x(out);
  p.kl = GaussianKl(p.post_mean, p.post_logvar, p.prior_mean, p.prior_logvar).sum({1, 2});
  return p;
}

std::pair<torch::Tensor, torch::Tensor> DvaeNetImpl::InitialState(const torch::Tensor& seq) {
  // Anticausal: run from y_T back to y_0, so the state that predicts x0 saw y_0 last.
  const torch::Tensor h = std::get<0>(r_h->forward(seq.flip(1)));
  const auto q = e_x0(h.select(1, h.size(1) - 1)).chunk(2, 1);
  return {q[0], q[1].clamp(kLogVarMin, kLogVarMax)};
}

DvaeNoise DvaeNetImpl::NoiseVariances(const torch::Tensor& y, const torch::Tensor& frames,
                                      const torch::Tensor& hidden, const torch::Tensor& scale2) {
  const double a0 = 2.0;  // alpha at initialisation
  const auto ab = e_b(torch::cat({hidden, y, y - frames}, 2)).chunk(2, 2);
  DvaeNoise n;
  n.alpha = torch::nn::functional::softplus(ab[0] + std::log(std::exp(a0) - 1.0)) + 1e-2;
  n.beta = n.alpha * scale2 * torch::exp(ab[1].clamp(-15, 15));
  return n;
}

torch::Tensor DvaeNetImpl::Generate(const torch::Tensor& x0, int64_t frames, bool sample_latents,
                                    at::Generator gen) {
  torch::Tensor h = d_ini(x0), c = torch::zeros_like(h);
  std::vector<torch::Tensor> out;
  for (int64_t t = 0; t < frames; ++t) {
    const auto prior = d_z(h).chunk(2, 1);
    torch::Tensor z = prior[0];
    if (sample_latents)
      z = z + torch::exp(0.5 * prior[1].clamp(kLogVarMin, kLogVarMax)) * Noise(z, gen);
    auto state = std::get<1>(
        dec_lstm->forward(z.unsqueeze(1), std::make_tuple(h.unsqueeze(0), c.unsqueeze(0))));
    h = std::get<0>(state).squeeze(0);
    c = std::get<1>(state).squeeze(0);
    out.push_back(d_x(h));
  }
  return torch::stack(out, 1);
}

std::vector<torch::Tensor> DvaeNetImpl::EncoderParameters() {
  std::vector<torch::Tensor> p;
  for (torch::nn::Module* m :
       std::vector<torch::nn::Module*>{e_ini.get(), e_glob.get(), e_data.get(), e_lat.get(),
                                       r_h.get(), e_x0.get(), e_b.get()}) {
    for (const torch::Tensor& t : m->parameters()) p.push_back(t);
  }
  return p;
}

std::vector<torch::Tensor> DvaeNetImpl::DecoderParameters() {
  std::vector<torch::Tensor> p;
  for (torch::nn::Module* m :
       std::vector<torch::nn::Module*>{d_ini.get(), d_x.get(), d_z.get(), dec_lstm.get()}) {
    for (const torch::Tensor& t : m->parameters()) p.push_back(t);
  }
  p.push_back(x_logvar);
  return p;
}

torch::Tensor GaussianKl(const torch::Tensor& m1, const torch::Tensor& l1, const torch::Tensor& m2,
                         const torch::Tensor& l2) {
  return 0.5 * (l2 - l1 + (torch::exp(l1) + (m1 - m2).pow(2)) * torch::exp(-l2) - 1.0);
}

torch::Tensor InverseGammaKl(const torch::Tensor& a, const torch::Tensor& b, double a0,
                             const torch::Tensor& b0) {
  return (a - a0) * torch::digamma(a) - torch::lgamma(a) + std::lgamma(a0) +
         a0 * (torch::log(b) - torch::log(b0)) + a * (b0 - b) / b;
}

int DvaeValues(const DvaeManifest& m) {
  return 3 * static_cast<int>(m.skeleton.joint_names.size());
}

DvaeNet BuildDvaeNet(const DvaeManifest& m) { return DvaeNet(m.model, DvaeValues(m), m.refiner); }

}  // namespace motionfork
