#include "imputation/hgvae_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/parallel_for.h"
#include "imputation/hgvae_net.h"
#include "imputation/hgvae_tensors.h"
#include "imputation/refiner_adaptation.h"
#include "refine/refiner_windows.h"
#include "torch_util/parameters.h"

namespace motionfork {

namespace {
constexpr int64_t kChunk = 64;  // windows per pass; fixed, so results do not depend on threads
constexpr int64_t kSampleChunk = 256;  // windows drawn per pass (one generator for all)

// Runs fn(first window, windows) for every chunk of `count` windows on up to `threads` threads and
// returns the chunks' results in order.
template <typename Fn>
auto ForChunks(int64_t count, int threads, Fn fn) {
  const int chunks = static_cast<int>((count + kChunk - 1) / kChunk);
  std::vector<decltype(fn(int64_t{0}, int64_t{0}))> out(static_cast<size_t>(chunks));
  ParallelFor(chunks, threads, [&](int c, int) {
    const int64_t s = c * kChunk;
    out[static_cast<size_t>(c)] = fn(s, std::min(kChunk, count - s));
  });
  return out;
}

template <typename T>
void Append(std::vector<T>* dst, const std::vector<T>& src) {
  dst->insert(dst->end(), src.begin(), src.end());
}

void AppendTensor(std::vector<double>* dst, const torch::Tensor& t) {
  const torch::Tensor d = t.to(torch::kFloat64).contiguous();
  dst->insert(dst->end(), d.data_ptr<double>(), d.data_ptr<double>() + d.numel());
}
}  // namespace

struct HgvaeModel::Impl {
  // Inference only: no parameter needs a gradient.
  Impl(HgvaeManifest m, HgvaeNet n)
      : manifest(std::move(m)),
        skeleton(std::make_shared<const Skeleton>(Skeleton::Build(manifest.skeleton))),
        net(std::move(n)),
        tensors(std::make_unique<HgvaeTensors>(manifest)) {
    for (auto& p : net->parameters()) p.set_requires_grad(false);
    for (double s : manifest.std) log_det += T() * std::log(s);
  }

  HgvaeManifest manifest;
  std::shared_ptr<const Skeleton> skeleton;
  mutable HgvaeNet net{nullptr};
  std::unique_ptr<HgvaeTensors> tensors;
  double log_det = 0;  // T * sum log std: normalised -> metres densities

  int64_t T() const { return manifest.model.window; }
  int64_t N() const { return static_cast<int64_t>(manifest.mean.size()); }

  torch::Tensor Labels(int class_index, int64_t count) const {
    if (class_index < 0) return {};
    torch::Tensor l = torch::zeros({count, static_cast<int64_t>(manifest.classes.size())});
    l.select(1, class_index).fill_(1.0f);
    return l;
  }

  int64_t CheckWindows(const std::vector<float>& w, const char* what) const {
    const size_t per = static_cast<size_t>(T() * N());
    if (w.empty() || w.size() % per != 0) {
      throw std::invalid_argument(std::string(what) + ": expected windows of " +
                                  std::to_string(T()) + " frames x " + std::to_string(N()) +
                                  " coordinates (a multiple of " + std::to_string(per) +
                                  " values), got " + std::to_string(w.size()) + " values");
    }
    return static_cast<int64_t>(w.size() / per);
  }

  // Per window [B]: the imputation objective `objective` and the bundle's OoD score.
  std::pair<torch::Tensor, torch::Tensor> Objective(const torch::Tensor& x,
                                                    const torch::Tensor& labels,
                                                    ImputeObjective objective) const {
    const HgvaeOutput o = net->forward(x, labels, LatentMode::kPosteriorMean);
    const torch::Tensor first = net->Score(x, o, objective);
    return {first, objective == manifest.ood_score ? first : net->Score(x, o, manifest.ood_score)};
  }
};

HgvaeModel HgvaeModel::FromNet(HgvaeManifest manifest, HgvaeNet net) {
  HgvaeModel m;
  m.impl_ = std::make_shared<Impl>(std::move(manifest), std::move(net));
  return m;
}

const HgvaeManifest& HgvaeModel::manifest() const { return impl_->manifest; }
const Skeleton& HgvaeModel::skeleton() const { return *impl_->skeleton; }
int HgvaeModel::window() const { return static_cast<int>(impl_->T()); }
int HgvaeModel::coords() const { return static_cast<int>(impl_->N()); }
int64_t HgvaeModel::num_parameters() const { return CountParameters(*impl_->net); }

void HgvaeModel::set_threads(int threads) {
  if (threads < 1)
    throw std::invalid_argument("HgvaeModel: expected >= 1 thread, got " + std::to_string(threads));
  threads_ = threads;
}

int HgvaeModel::ClassIndex(const std::string& name) const {
  if (name.empty()) return -1;
  const auto& c = impl_->manifest.classes;
  const auto it = std::find(c.begin(), c.end(), name);
  if (it != c.end()) return static_cast<int>(it - c.begin());
  std::string list;
  for (const auto& n : c) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown class '" + name + "'" +
                              (c.empty() ? " (this model is unconditional: it has no classes)"
                                         : " (the model's classes: " + list + ")"));
}

double HgvaeModel::OodThreshold() const {
  return impl_->manifest.score_mean - impl_->manifest.ood_k * impl_->manifest.score_std;
}

std::vector<double> HgvaeModel::Score(const std::vector<float>& windows, int class_index) const {
  return Score(windows, impl_->manifest.ood_score, class_index);
}

std::vector<double> HgvaeModel::Score(const std::vector<float>& windows, ImputeObjective score,
                                      int class_index) const {
  const Impl& im = *impl_;
  const int64_t count = im.CheckWindows(windows, "Score");
  const auto chunks = ForChunks(count, threads_, [&](int64_t s, int64_t n) {
    torch::NoGradGuard no_grad;
    const torch::Tensor x = im.tensors->ToNodeMajor(windows.data() + s * im.T() * im.N(), n);
    std::vector<double> out;
    AppendTensor(&out, im.Objective(x, im.Labels(class_index, n), score).first);
    return out;
  });
  std::vector<double> out;
  for (const auto& c : chunks) Append(&out, c);
  return out;
}

std::vector<float> HgvaeModel::MeanImpute(const std::vector<float>& windows,
                                          const std::vector<uint8_t>& missing) const {
  const Impl& im = *impl_;
  im.CheckWindows(windows, "MeanImpute");
  if (missing.size() != windows.size())
    throw std::invalid_argument("MeanImpute: mask and windows differ in size");
  std::vector<float> out = windows;
  for (size_t i = 0; i < out.size(); ++i) {
    if (missing[i]) out[i] = static_cast<float>(im.manifest.mean[i % im.N()]);
  }
  return out;
}

ImputeResult HgvaeModel::Impute(const std::vector<float>& windows,
                                const std::vector<uint8_t>& missing, const ImputeOptions& options,
                                int class_index, const std::vector<float>* start) const {
  const Impl& im = *impl_;
  const int64_t count = im.CheckWindows(windows, "Impute");
  if (missing.size() != windows.size() || (start && start->size() != windows.size())) {
    throw std::invalid_argument("Impute: the mask has " + std::to_string(missing.size()) +
                                " values, the windows " + std::to_string(windows.size()) +
                                (start ? ", the start " + std::to_string(start->size()) : ""));
  }
  const size_t per = static_cast<size_t>(im.T() * im.N());
  for (int64_t w = 0; w < count; ++w) {
    const auto first = missing.begin() + w * per;
    if (std::all_of(first, first + per, [](uint8_t v) { return v != 0; })) {
      throw std::invalid_argument("Impute: window " + std::to_string(w) +
                                  " has every value missing: nothing to impute from");
    }
  }
  const auto chunks = ForChunks(count, threads_, [&](int64_t s, int64_t n) {
    const torch::Tensor mask = im.tensors->MaskToNodeMajor(missing.data() + s * per, n);
    const torch::Tensor raw = im.tensors->ToNodeMajor(windows.data() + s * per, n);
    // Missing -> the start's values, or the mean (0 in normalised coordinates).
    const torch::Tensor from =
        start ? im.tensors->ToNodeMajor(start->data() + s * per, n) : torch::zeros_like(raw);
    const torch::Tensor x0 = torch::where(mask > 0, from, raw);
    const torch::Tensor labels = im.Labels(class_index, n);
    torch::Tensor v = torch::zeros_like(x0).requires_grad_(true);
    torch::optim::Adam adam({v}, torch::optim::AdamOptions(options.learning_rate));
    torch::Tensor best_obj = torch::full({n}, -std::numeric_limits<float>::infinity());
    torch::Tensor best_score = torch::zeros({n}), before;
    torch::Tensor best_x = x0.clone(), best_step = torch::zeros({n}, torch::kInt64);
    for (int step = 0; step <= options.steps; ++step) {
      const torch::Tensor x = x0 + v * mask;
      auto [obj, score] = im.Objective(x, labels, options.objective);
      {
        torch::NoGradGuard no_grad;
        if (step == 0) before = score.detach().clone();
        const torch::Tensor better = obj.detach() > best_obj;
        best_obj = torch::where(better, obj.detach(), best_obj);
        best_score = torch::where(better, score.detach(), best_score);
        best_step = torch::where(better, torch::full_like(best_step, step), best_step);
        best_x = torch::where(better.view({1, n, 1}), x.detach(), best_x);
      }
      if (step == options.steps) break;
      adam.zero_grad();
      (-obj.sum()).backward();
      adam.step();
    }
    ImputeResult r;
    const std::vector<float> filled = im.tensors->FromNodeMajor(best_x);
    // Observed values are returned exactly as given (no round trip through the normalisation).
    for (size_t i = 0; i < filled.size(); ++i) {
      const size_t g = static_cast<size_t>(s) * per + i;
      r.windows.push_back(missing[g] ? filled[i] : windows[g]);
    }
    AppendTensor(&r.score_before, before);
    AppendTensor(&r.score_after, best_score);
    for (int64_t i = 0; i < n; ++i)
      r.best_step.push_back(static_cast<int>(best_step[i].item<int64_t>()));
    return r;
  });
  ImputeResult r;
  r.windows.reserve(windows.size());
  for (const ImputeResult& c : chunks) {
    Append(&r.windows, c.windows);
    Append(&r.score_before, c.score_before);
    Append(&r.score_after, c.score_after);
    Append(&r.best_step, c.best_step);
  }
  return r;
}

HgvaeWindowFigures HgvaeModel::Evaluate(const std::vector<float>& windows, uint64_t seed) const {
  const Impl& im = *impl_;
  const int64_t count = im.CheckWindows(windows, "Evaluate");
  const int64_t levels = im.net->num_levels();
  const auto chunks = ForChunks(count, threads_, [&](int64_t s, int64_t n) {
    torch::NoGradGuard no_grad;
    at::Generator gen =
        at::make_generator<at::CPUGeneratorImpl>(ItemSeed(seed, static_cast<int>(s / kChunk)));
    HgvaeWindowFigures f;
    f.kl_levels.resize(levels);
    const torch::Tensor x = im.tensors->ToNodeMajor(windows.data() + s * im.T() * im.N(), n);
    const HgvaeOutput o = im.net->forward(x, {}, LatentMode::kSample, gen);
    AppendTensor(&f.elbo,
                 HgvaeNetImpl::GaussianLogLik(x, o.x_mean, o.x_logvar) - o.kl - im.log_det);
    AppendTensor(&f.recon_mse_sampled,
                 im.tensors->SquaredErrorMetres(x, o.x_mean).mean(std::vector<int64_t>{0, 2}));
    for (int64_t l = 0; l < levels; ++l) AppendTensor(&f.kl_levels[l], o.kl_levels[l]);
    const HgvaeOutput om = im.net->forward(x, {}, LatentMode::kPosteriorMean);
    AppendTensor(&f.score, im.net->Score(x, om, ImputeObjective::kPosterior));
    AppendTensor(&f.joint_score, im.net->Score(x, om, ImputeObjective::kJoint));
    AppendTensor(&f.recon_mse,
                 im.tensors->SquaredErrorMetres(x, om.x_mean).mean(std::vector<int64_t>{0, 2}));
    return f;
  });
  HgvaeWindowFigures f;
  f.kl_levels.resize(levels);
  for (const HgvaeWindowFigures& c : chunks) {
    Append(&f.elbo, c.elbo);
    Append(&f.recon_mse_sampled, c.recon_mse_sampled);
    for (int64_t l = 0; l < levels; ++l) Append(&f.kl_levels[l], c.kl_levels[l]);
    Append(&f.score, c.score);
    Append(&f.joint_score, c.joint_score);
    Append(&f.recon_mse, c.recon_mse);
  }
  return f;
}

std::vector<float> HgvaeModel::Sample(int count, int class_index, uint64_t seed,
                                      bool sample_latents) const {
  const Impl& im = *impl_;
  if (count < 1)
    throw std::invalid_argument("Sample: expected a count >= 1, got " + std::to_string(count));
  torch::NoGradGuard no_grad;
  at::Generator gen = at::make_generator<at::CPUGeneratorImpl>(seed);
  std::vector<float> out;
  for (int64_t s = 0; s < count; s += kSampleChunk) {
    const int64_t n = std::min<int64_t>(kSampleChunk, count - s);
    const std::vector<float> w = im.tensors->FromNodeMajor(
        im.net->Generate(n, im.Labels(class_index, n), sample_latents, gen));
    out.insert(out.end(), w.begin(), w.end());
  }
  return out;
}

ImputationBlend HgvaeModel::calibrated_blend() const {
  const HgvaeManifest& m = impl_->manifest;
  return {m.refiner_weights,        m.refiner_local_weights,
          m.refiner_keep_bones,     {},
          m.refiner_adapt_values,   m.refiner_smoothing,
          m.refiner_gaussian.model, m.refiner_gaussian.scope};
}

bool HgvaeModel::has_refiner() const { return static_cast<bool>(impl_->net->refiner); }

std::vector<float> HgvaeModel::Refine(const RefinerFills& f, bool calibrated) const {
  const Impl& im = *impl_;
  if (!has_refiner()) {
    throw std::invalid_argument(
        "impute: start 'refiner' needs a bundle with a refiner (motionfork hgvae refine)");
  }
  torch::NoGradGuard no_grad;
  const torch::Tensor in = im.tensors->RefinerInput(f)[0];
  const RefinerOptions& r = im.manifest.refiner;
  const torch::Tensor corrected =
      im.tensors->Refined(in, RefineInWindows(im.net->refiner, in, r.window, r.stride));
  const torch::Tensor metres =
      im.tensors->DenormaliseFrameMajor(corrected.unsqueeze(0)).contiguous();
  std::vector<float> refined(metres.data_ptr<float>(), metres.data_ptr<float>() + metres.numel());
  const ImputationBlend blend = calibrated_blend();
  if (!calibrated || (blend.refiner.empty() && blend.local.empty() && !blend.keep_bones &&
                      !AdaptsToMotion(blend) && !blend.smoothing.active() && !blend.gaussian))
    return refined;
  const RawRefiner raw = [this](const RefinerFills& probe) { return Refine(probe, false); };
  return BlendRefinerFills(skeleton(), f, refined, AdaptToMotion(skeleton(), f, raw, blend));
}

}  // namespace motionfork
