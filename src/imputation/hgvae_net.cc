#include "imputation/hgvae_net.h"

#include <cmath>

#include "core/dct.h"

namespace motionfork {

namespace {

constexpr double kLog2Pi = 1.8378770664093453;
// Log-variances are clamped as in the released code (a variance of 1e-9..20 in normalised units).
constexpr double kMinLogVar = -20.0, kMaxLogVar = 3.0;

std::pair<torch::Tensor, torch::Tensor> SplitGaussian(const torch::Tensor& y) {
  auto halves = y.chunk(2, /*dim=*/2);
  return {halves[0], halves[1].clamp(kMinLogVar, kMaxLogVar)};
}

// [n, B, f] summed to [B].
torch::Tensor SumPerWindow(const torch::Tensor& t) { return t.sum(std::vector<int64_t>{0, 2}); }

torch::Tensor GaussianKl(const torch::Tensor& mq, const torch::Tensor& lq, const torch::Tensor& mp,
                         const torch::Tensor& lp) {
  return SumPerWindow(0.5 * (lp - lq + (lq.exp() + (mq - mp).pow(2)) * (-lp).exp() - 1.0));
}

}  // namespace

HgvaeGraphConvImpl::HgvaeGraphConvImpl(int64_t in_nodes, int64_t out_nodes, int64_t in_features,
                                       int64_t out_features) {
  // As the released code (and LTD): uniform(-1/sqrt(out_features), +) for every parameter.
  const double stdv = 1.0 / std::sqrt(static_cast<double>(out_features));
  adjacency =
      register_parameter("adjacency", torch::empty({out_nodes, in_nodes}).uniform_(-stdv, stdv));
  weight =
      register_parameter("weight", torch::empty({in_features, out_features}).uniform_(-stdv, stdv));
  bias =
      register_parameter("bias", torch::empty({out_nodes, 1, out_features}).uniform_(-stdv, stdv));
}

torch::Tensor HgvaeGraphConvImpl::forward(const torch::Tensor& x) {
  const int64_t nin = x.size(0), B = x.size(1), fin = x.size(2);
  const int64_t nout = adjacency.size(0), fout = weight.size(1);
  // Either order of the two products gives the same result; take the cheaper one.
  const double cost_weight_first = double(nin) * B * fin * fout + double(nout) * nin * B * fout;
  const double cost_nodes_first = double(nout) * nin * B * fin + double(nout) * B * fin * fout;
  if (cost_weight_first <= cost_nodes_first) {
    const torch::Tensor support = x.reshape({nin * B, fin}).mm(weight);
    return adjacency.mm(support.view({nin, B * fout})).view({nout, B, fout}) + bias;
  }
  const torch::Tensor mixed = adjacency.mm(x.reshape({nin, B * fin}));
  return mixed.view({nout * B, fin}).mm(weight).view({nout, B, fout}) + bias;
}

HgvaeBlockImpl::HgvaeBlockImpl(int64_t nodes, int64_t features) {
  first = register_module("first", HgvaeGraphConv(nodes, nodes, features, features));
  second = register_module("second", HgvaeGraphConv(nodes, nodes, features, features));
  alpha = register_parameter("alpha", torch::zeros({1}));
}

torch::Tensor HgvaeBlockImpl::forward(const torch::Tensor& x) {
  return x + alpha * torch::gelu(second(torch::gelu(first(x))));
}

HgvaeNetImpl::HgvaeNetImpl(const HgvaeOptions& options, int64_t num_coords, int64_t frames,
                           int64_t classes, const RefinerOptions& refine)
    : options_(options), num_coords_(num_coords), frames_(frames), classes_(classes) {
  const int64_t L = num_levels(), W = options.width;
  auto nodes = [&](int64_t l) -> int64_t { return options_.levels[l].nodes; };
  auto feats = [&](int64_t l) -> int64_t { return options_.levels[l].features; };
  TORCH_CHECK(nodes(L - 1) == num_coords,
              "HgvaeNet: the bottom level must have every coordinate as a node");
  const Eigen::MatrixXd d = DctMatrix(static_cast<int>(frames));
  dct_ = torch::empty({frames, frames});
  for (int64_t i = 0; i < frames; ++i)
    for (int64_t j = 0; j < frames; ++j) dct_[i][j] = d(i, j);
  dct_ = register_buffer("dct", dct_);

  auto blocks = [&](int count, int64_t n, int64_t f) {
    torch::nn::Sequential s;
    for (int b = 0; b < count; ++b) s->push_back(HgvaeBlock(n, f));
    return s;
  };
  enc_input =
      register_module("enc_input", HgvaeGraphConv(num_coords, num_coords, frames, feats(L - 1)));
  enc_contract.assign(L, HgvaeGraphConv(nullptr));
  dec_expand.assign(L, HgvaeGraphConv(nullptr));
  prior_head.assign(L, HgvaeGraphConv(nullptr));
  post_head.assign(L, HgvaeGraphConv(nullptr));
  z_in.assign(L, HgvaeGraphConv(nullptr));
  enc_blocks.assign(L, torch::nn::Sequential(nullptr));
  dec_blocks.assign(L, torch::nn::Sequential(nullptr));
  for (int64_t l = 0; l < L; ++l) {
    const std::string s = std::to_string(l);
    enc_blocks[l] =
        register_module("enc_blocks" + s, blocks(options.encoder_blocks, nodes(l), feats(l)));
    if (l < L - 1) {
      enc_contract[l] = register_module(
          "enc_contract" + s, HgvaeGraphConv(nodes(l + 1), nodes(l), feats(l + 1), feats(l)));
    }
    if (l == 0) {
      dec_top =
          register_module("dec_top", HgvaeGraphConv(nodes(0), nodes(0), feats(0) + classes, W));
      post_head[0] =
          register_module("post_head0", HgvaeGraphConv(nodes(0), nodes(0), feats(0), 2 * feats(0)));
    } else {
      dec_expand[l] =
          register_module("dec_expand" + s, HgvaeGraphConv(nodes(l - 1), nodes(l), W, W));
      prior_head[l] =
          register_module("prior_head" + s, HgvaeGraphConv(nodes(l), nodes(l), W, 2 * feats(l)));
      post_head[l] = register_module(
          "post_head" + s, HgvaeGraphConv(nodes(l), nodes(l), W + feats(l), 2 * feats(l)));
      z_in[l] = register_module("z_in" + s, HgvaeGraphConv(nodes(l), nodes(l), feats(l), W));
    }
    dec_blocks[l] = register_module("dec_blocks" + s, blocks(options.decoder_blocks, nodes(l), W));
  }
  out_head = register_module(
      "out_head",
      HgvaeGraphConv(num_coords, num_coords, W, options.predicted_variance ? 2 * frames : frames));
  if (!options.predicted_variance)
    out_logvar = register_parameter("out_logvar", torch::zeros({num_coords, 1, frames}));
  if (refine.enabled()) {
    refiner = register_module("refiner",
                              TemporalRefiner(refine, kRefinerChannels * num_coords, num_coords));
  }
}

bool HgvaeNetImpl::stochastic(int64_t level) const {
  return options_.stochastic_levels == 0 || level < options_.stochastic_levels;
}

torch::Tensor HgvaeNetImpl::GaussianLogLik(const torch::Tensor& x, const torch::Tensor& mean,
                                           const torch::Tensor& logvar) {
  return SumPerWindow(-0.5 * (kLog2Pi + logvar + (x - mean).pow(2) * (-logvar).exp()));
}

torch::Tensor HgvaeNetImpl::TopDown(const std::vector<torch::Tensor>* encoded,
                                    const torch::Tensor& labels, int64_t batch, LatentMode mode,
                                    bool from_prior, c10::optional<at::Generator> gen,
                                    HgvaeOutput* out) {
  const int64_t L = num_levels();
  torch::Tensor path;
  torch::Tensor kl = torch::zeros({batch});
  for (int64_t l = 0; l < L; ++l) {
    const int64_t n = options_.levels[l].nodes, f = options_.levels[l].features;
    torch::Tensor pm, plv;
    if (l == 0) {
      pm = torch::zeros({n, batch, f});
      plv = torch::zeros({n, batch, f});
    } else {
      path = torch::gelu(dec_expand[l](path));
      std::tie(pm, plv) = SplitGaussian(prior_head[l](path));
    }
    torch::Tensor z, qm, qlv, kl_l = torch::zeros({batch});
    if (!stochastic(l)) {
      z = pm;  // off: the prior's mean, no information from x, no KL
    } else if (from_prior) {
      z = mode == LatentMode::kSample ? pm + (0.5 * plv).exp() * torch::randn(pm.sizes(), gen) : pm;
    } else {
      const torch::Tensor& a = (*encoded)[l];
      std::tie(qm, qlv) =
          SplitGaussian(l == 0 ? post_head[0](a) : post_head[l](torch::cat({path, a}, 2)));
      z = mode == LatentMode::kSample ? qm + (0.5 * qlv).exp() * torch::randn(qm.sizes(), gen) : qm;
      kl_l = GaussianKl(qm, qlv, pm, plv);
      kl = kl + kl_l;
    }
    if (l == 0) {
      torch::Tensor top = z;
      if (classes_ > 0) {
        const torch::Tensor onehot = labels.defined() ? labels : torch::zeros({batch, classes_});
        top = torch::cat({z, onehot.unsqueeze(0).expand({n, batch, classes_})}, 2);
      }
      path = torch::gelu(dec_top(top));
    } else {
      path = path + torch::gelu(z_in[l](z));
    }
    path = dec_blocks[l]->forward(path);
    if (out) {
      out->prior_mean.push_back(pm);
      out->prior_logvar.push_back(plv);
      out->post_mean.push_back(qm);
      out->post_logvar.push_back(qlv);
      out->z.push_back(z);
      out->kl_levels.push_back(kl_l);
    }
  }
  if (out) out->kl = kl;
  return path;
}

HgvaeOutput HgvaeNetImpl::forward(const torch::Tensor& x, const torch::Tensor& labels,
                                  LatentMode mode, c10::optional<at::Generator> gen) {
  const int64_t L = num_levels(), B = x.size(1);
  std::vector<torch::Tensor> encoded(L);
  torch::Tensor a = torch::gelu(enc_input(x.matmul(dct_.t())));
  for (int64_t l = L - 1; l >= 0; --l) {
    if (l < L - 1) a = torch::gelu(enc_contract[l](a));
    a = enc_blocks[l]->forward(a);
    encoded[l] = a;
  }
  HgvaeOutput out;
  const torch::Tensor path = TopDown(&encoded, labels, B, mode, false, gen, &out);
  std::tie(out.x_mean, out.x_logvar) = Output(path);
  return out;
}

torch::Tensor HgvaeNetImpl::Generate(int64_t count, const torch::Tensor& labels,
                                     bool sample_latents, at::Generator gen) {
  const torch::Tensor path = TopDown(
      nullptr, labels, count, sample_latents ? LatentMode::kSample : LatentMode::kPosteriorMean,
      true, gen, nullptr);
  return Output(path).first;
}

std::pair<torch::Tensor, torch::Tensor> HgvaeNetImpl::Output(const torch::Tensor& path) {
  if (options_.predicted_variance) {
    auto [mean_dct, logvar] = SplitGaussian(out_head(path));
    return {mean_dct.matmul(dct_), logvar};
  }
  const torch::Tensor mean = out_head(path).matmul(dct_);
  return {mean, out_logvar.clamp(kMinLogVar, kMaxLogVar).expand_as(mean)};
}

torch::Tensor HgvaeNetImpl::PosteriorScore(const HgvaeOutput& out) const {
  torch::Tensor score = torch::zeros_like(out.kl);
  for (int64_t l = 0; l < num_levels(); ++l) {
    if (!stochastic(l)) continue;
    score = score + GaussianLogLik(out.post_mean[l], out.prior_mean[l], out.prior_logvar[l]);
  }
  return score;
}

torch::Tensor HgvaeNetImpl::Score(const torch::Tensor& x, const HgvaeOutput& out,
                                  ImputeObjective which) const {
  const torch::Tensor posterior = PosteriorScore(out);
  return which == ImputeObjective::kPosterior
             ? posterior
             : posterior + GaussianLogLik(x, out.x_mean, out.x_logvar);
}

int HgvaeCoords(const HgvaeManifest& m) {
  return 3 * (static_cast<int>(m.skeleton.joint_names.size()) - 1);
}

HgvaeNet BuildHgvaeNet(const HgvaeManifest& m) {
  return HgvaeNet(m.model, HgvaeCoords(m), m.model.window, static_cast<int64_t>(m.classes.size()),
                  m.refiner);
}

}  // namespace motionfork
