#include "generator/model/generator_net.h"

#include <condition_variable>
#include <mutex>
#include <thread>

#include "core/dct.h"
#include "generator/kernels/backend.h"
#include "generator/model/fused_ops.h"
#include "generator/model/latents.h"
#include "torch_catch.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

GeneratorOptions Tiny() {
  GeneratorOptions o;
  o.num_nodes = 6;
  o.t_his = 5;
  o.t_pred = 10;
  o.n_pre = 4;
  o.hidden = 16;
  o.blocks = 2;
  o.nz = 3;
  return o;
}

std::vector<std::vector<int64_t>> TwoParts() { return {{0, 1, 2}, {3, 4, 5}}; }

}  // namespace

TEST_CASE("generator encodes the padded history with the orthonormal DCT") {
  PinThreads(1);
  torch::manual_seed(0);
  GeneratorNet net(Tiny(), TwoParts());
  const torch::Tensor h = torch::randn({2, 5, 6, 3});
  const torch::Tensor c = net->EncodeHistory(h);
  REQUIRE(c.sizes() == torch::IntArrayRef({6, 2, 12}));
  // Independent: pad by hand, DCT with Eigen, compare coefficient l of node 4, axis y, history 1.
  const Eigen::MatrixXd d = DctMatrix(15);
  for (int l = 0; l < 4; ++l) {
    double want = 0;
    for (int t = 0; t < 15; ++t) want += d(l, t) * h[1][std::min(t, 4)][4][1].item<float>();
    CHECK(c[4][1][1 * 4 + l].item<float>() == Approx(want).margin(1e-5));
  }
  // With all coefficients kept, Frames(Encode(h)) reproduces the padded history.
  GeneratorOptions full = Tiny();
  full.n_pre = 15;
  GeneratorNet lossless(full, TwoParts());
  const torch::Tensor back = lossless->Frames(lossless->EncodeHistory(h));
  CHECK(torch::allclose(back.slice(1, 0, 5), h, 1e-5, 1e-5));
  CHECK(torch::allclose(back.select(1, 14), h.select(1, 4), 1e-5, 1e-5));
}

TEST_CASE("generator shapes, parts in sequence and part control") {
  PinThreads(1);
  torch::manual_seed(1);
  GeneratorNet net(Tiny(), TwoParts());
  net->eval();
  torch::NoGradGuard no_grad;
  const torch::Tensor h = torch::randn({2, 5, 6, 3});
  const int64_t K = 7;
  std::vector<torch::Tensor> z = {torch::randn({2 * K, 3}), torch::randn({2 * K, 3})};
  const torch::Tensor y = net->forward(h, z);
  REQUIRE(y.sizes() == torch::IntArrayRef({14, 15, 6, 3}));
  // Same latents -> same futures.
  CHECK(torch::equal(y, net->forward(h, z)));
  // Fix part 0's latent across samples: its nodes are identical in all K futures, part 1 varies.
  std::vector<torch::Tensor> fixed = {
      z[0].view({2, K, 3}).select(1, 0).unsqueeze(1).expand({2, K, 3}).reshape({2 * K, 3}), z[1]};
  // Max over samples of the difference to sample 0, for joints [from, to) of futures [2, K, ...].
  const auto spread = [](const torch::Tensor& f, int64_t from, int64_t to) {
    const torch::Tensor j = f.slice(3, from, to);
    return (j - j.select(1, 0).unsqueeze(1)).abs().max().item<float>();
  };
  // Told which part is fixed (as Forecaster does), the part is bit-identical across samples.
  const torch::Tensor f = net->forward(h, fixed, {true, false}).view({2, K, 15, 6, 3});
  CHECK(spread(f, 0, 3) == 0.0f);
  CHECK(spread(f, 3, 6) > 1e-3f);
  // The flag alone decides: a part flagged fixed takes each history's first sample's output even
  // when the latents differ (callers pass equal ones; this shows the copy is made).
  const torch::Tensor copied = net->forward(h, z, {true, false}).view({2, K, 15, 6, 3});
  CHECK(spread(copied, 0, 3) == 0.0f);
  CHECK(spread(net->forward(h, z).view({2, K, 15, 6, 3}), 0, 3) > 1e-3f);
  // Not told, the same latent in every sample gives the same legs up to the rounding of matrix
  // products whose row blocks differ (OpenBLAS's Haswell kernels on an AMD EPYC differ at about
  // 1e-7; the flag above is what makes control exact).
  const torch::Tensor u = net->forward(h, fixed).view({2, K, 15, 6, 3});
  CHECK(spread(u, 0, 3) < 1e-5f);
  CHECK(torch::allclose(u, f, 1e-5, 1e-5));
  // Fixing the later part instead: part 0 varies; part 1, which sees part 0's output, varies too
  // unless flagged as fixed, when it is computed from each history's first sample.
  std::vector<torch::Tensor> fix_second = {z[0], fixed[0]};
  const torch::Tensor g = net->forward(h, fix_second).view({2, K, 15, 6, 3});
  CHECK(spread(g, 0, 3) > 1e-3f);
  CHECK(spread(g, 3, 6) > 1e-3f);
  const torch::Tensor gf = net->forward(h, fix_second, {false, true}).view({2, K, 15, 6, 3});
  CHECK(spread(gf, 0, 3) > 1e-3f);
  CHECK(spread(gf, 3, 6) == 0.0f);
}

TEST_CASE("every generator parameter receives a gradient") {
  PinThreads(1);
  torch::manual_seed(2);
  REQUIRE(Tiny().batch_norm);
  GeneratorNet net(Tiny(), TwoParts());
  net->train();
  const torch::Tensor h = torch::randn({3, 5, 6, 3});
  std::vector<torch::Tensor> z = {torch::randn({12, 3}), torch::randn({12, 3})};
  net->forward(h, z).pow(2).mean().backward();
  for (const auto& p : net->named_parameters()) {
    INFO(p.key());
    REQUIRE(p.value().grad().defined());
    const float size = p.value().grad().abs().sum().item<float>();
    // A graph layer's conv bias comes before its batch norm, which cancels it: exactly zero.
    const std::string name = p.key();
    const bool cancelled = name.size() > 10 && name.substr(name.size() - 10) == ".conv.bias";
    if (cancelled) {
      CHECK(size == 0);
    } else {
      CHECK(size > 0);
    }
  }
}

TEST_CASE("generator rejects mismatched inputs") {
  GeneratorNet net(Tiny(), TwoParts());
  CHECK_THROWS_WITH(net->EncodeHistory(torch::randn({2, 4, 6, 3})),
                    Catch::Contains("expected history [B, 5, 6, 3]"));
  CHECK_THROWS_WITH(GeneratorNet(Tiny(), std::vector<std::vector<int64_t>>{{0, 1}, {3, 4, 5}}),
                    Catch::Contains("node 2 is in no body part"));
  CHECK_THROWS_WITH(net->Decode(torch::randn({6, 2, 12}), {torch::randn({2, 3})}),
                    Catch::Contains("expected 2 latents"));
}

TEST_CASE("fused batch norm + tanh matches the unfused LibTorch ops, values and gradients") {
  torch::manual_seed(5);
  // Widths below, at and across the AVX-512 kernels' 16-float blocks; both code paths.
  const bool portable = GENERATE(false, true);
  const std::vector<int64_t> shape =
      GENERATE(std::vector<int64_t>{4, 9, 7}, std::vector<int64_t>{3, 50, 16},
               std::vector<int64_t>{2, 33, 40});
  const bool with_bias = GENERATE(false, true);
  INFO("portable " << portable << ", shape " << c10::str(shape) << ", bias " << with_bias);
  kernels::UsePortableKernels(portable);
  const int64_t N = shape[0], H = shape[2];
  const torch::Tensor x0 = torch::randn(shape) * 2 + 0.5;
  const torch::Tensor g0 = torch::randn({N, 1, H}), b0 = torch::randn({N, 1, H}),
                      c0 = torch::randn({H});
  auto run = [&](bool fused) {
    torch::Tensor x = x0.clone().requires_grad_(true), g = g0.clone().requires_grad_(true),
                  b = b0.clone().requires_grad_(true), c = c0.clone().requires_grad_(true);
    torch::Tensor y, mean, var;
    if (fused) {
      y = BatchNormTanh(x, g, b, 1e-5, &mean, &var, with_bias ? c : torch::Tensor());
    } else {
      const torch::Tensor xc = with_bias ? x + c : x;
      mean = xc.mean(1, true);
      var = (xc - mean).pow(2).mean(1, true);
      y = torch::tanh((xc - mean) * torch::rsqrt(var + 1e-5) * g + b);
    }
    // Weights that do not sum to zero over the samples. The bias's gradient is zero all the same
    // (the normalisation cancels a shift): the fused op returns exact zeros, autograd rounding
    // noise.
    const torch::Tensor w = torch::linspace(-1, 1, y.numel()).view(y.sizes()).pow(3) + 0.1 * x0;
    (y * w).sum().backward();
    std::vector<torch::Tensor> out = {y.detach(), mean.detach(), var.detach(),
                                      x.grad(),   g.grad(),      b.grad()};
    if (with_bias) out.push_back(c.grad());
    return out;
  };
  const auto a = run(true), r = run(false);
  kernels::UsePortableKernels(false);
  for (size_t i = 0; i < a.size(); ++i) {
    INFO("output " << i);
    CHECK(torch::allclose(a[i], r[i], 1e-4, 1e-5));
  }
  if (with_bias) CHECK(a.back().abs().max().item<double>() == 0);
  const torch::Tensor t = torch::randn({1000}) * 5;
  CHECK(torch::allclose(FusedTanh(t), torch::tanh(t), 1e-6, 1e-6));
  const torch::Tensor s = torch::randn({N, 1, H}), sh = torch::randn({N, 1, H});
  CHECK(torch::allclose(ScaleShiftTanh(x0, s, sh), torch::tanh(x0 * s + sh), 1e-6, 1e-6));
}

namespace {

// Sums over two threads standing in for two workers: each calls Sum with its values and gets
// both threads' sums (in calls made in the same order on both).
class TwoThreadSum {
 public:
  void Sum(int me, std::vector<double>* values) {
    std::unique_lock<std::mutex> lock(mutex_);
    const int64_t round = round_;
    slot_[me] = *values;
    if (++arrived_ == 2) {
      arrived_ = 0;
      ++round_;
      changed_.notify_all();
    } else {
      changed_.wait(lock, [&] { return round_ != round; });
    }
    for (size_t i = 0; i < values->size(); ++i) (*values)[i] = slot_[0][i] + slot_[1][i];
    // Neither slot is refilled before both have been read.
    if (++read_ == 2) {
      read_ = 0;
      ++reads_done_;
      changed_.notify_all();
    } else {
      changed_.wait(lock, [&] { return reads_done_ != round; });
    }
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<double> slot_[2];
  int arrived_ = 0, read_ = 0;
  int64_t round_ = 0, reads_done_ = 0;
};

}  // namespace

TEST_CASE("synchronised batch norm on two shares gives the whole batch's values and gradients") {
  torch::manual_seed(7);
  const int64_t N = 3, B = 12, H = 20;
  const torch::Tensor x0 = torch::randn({N, B, H}) * 2 + 0.5;
  const torch::Tensor g0 = torch::randn({N, 1, H}), b0 = torch::randn({N, 1, H});
  const torch::Tensor w0 = torch::randn({N, B, H});
  // The whole batch's loss: sum(y * w) / B, a mean over the samples as the trainers' losses are.
  torch::Tensor x = x0.clone().requires_grad_(true), g = g0.clone().requires_grad_(true);
  torch::Tensor mean, var;
  const torch::Tensor y = BatchNormTanh(x, g, b0, 1e-5, &mean, &var);
  ((y * w0).sum() / B).backward();
  // Shares of 5 and 7 samples, each worker's loss the mean over its share; the gradients are then
  // weighted by the shares (share / B) and summed, as DataParallel::ReduceGradients does.
  const int64_t cut = 5;
  TwoThreadSum exchange;
  std::vector<torch::Tensor> ys(2), xgrads(2), ggrads(2), means(2);
  std::vector<double> rows(2);
  auto worker = [&](int me) {
    at::set_num_threads(1);
    const int64_t begin = me == 0 ? 0 : cut, size = me == 0 ? cut : B - cut;
    const double share = static_cast<double>(size) / B;
    const BatchSync sync{[&, me](std::vector<double>* v) { exchange.Sum(me, v); }, share};
    torch::Tensor xs = x0.slice(1, begin, begin + size).clone().requires_grad_(true);
    torch::Tensor gs = g0.clone().requires_grad_(true);
    torch::Tensor m, v;
    ys[me] = BatchNormTanh(xs, gs, b0, 1e-5, &m, &v, {}, &sync, &rows[me]);
    ((ys[me] * w0.slice(1, begin, begin + size)).sum() / size).backward();
    xgrads[me] = xs.grad() * share;
    ggrads[me] = gs.grad() * share;
    means[me] = m;
  };
  std::thread other(worker, 1);
  worker(0);
  other.join();
  CHECK(rows[0] == B);
  CHECK(rows[1] == B);
  CHECK(torch::allclose(torch::cat(ys, 1), y, 1e-5, 1e-6));
  CHECK(torch::equal(means[0], means[1]));
  CHECK(torch::allclose(means[0], mean, 1e-5, 1e-6));
  CHECK(torch::allclose(torch::cat(xgrads, 1), x.grad(), 1e-4, 1e-6));
  CHECK(torch::allclose(ggrads[0] + ggrads[1], g.grad(), 1e-4, 1e-6));
}

TEST_CASE("generator in eval mode gives the same futures through fused and plain paths") {
  torch::manual_seed(6);
  GeneratorNet net(Tiny(), TwoParts());
  // A few training-mode passes so that running statistics are not trivial.
  net->train();
  for (int i = 0; i < 3; ++i)
    net->forward(torch::randn({4, 5, 6, 3}), {torch::randn({8, 3}), torch::randn({8, 3})});
  net->eval();
  const torch::Tensor h = torch::randn({2, 5, 6, 3});
  std::vector<torch::Tensor> z = {torch::randn({6, 3}), torch::randn({6, 3})};
  torch::Tensor fused, plain;
  {
    torch::NoGradGuard no_grad;
    fused = net->forward(h, z);
  }
  plain = net->forward(h, z).detach();  // grad mode on: the unfused path
  CHECK(torch::allclose(fused, plain, 1e-5, 1e-5));
}

TEST_CASE(
    "nested training forward equals the full forward: futures, gradients, running statistics") {
  PinThreads(1);
  const std::vector<std::vector<int64_t>> three = {{0, 1}, {2, 3}, {4, 5}};
  const std::vector<int64_t> per_part = {2, 3, 2};
  torch::manual_seed(8);
  GeneratorNet full(Tiny(), three), nested(Tiny(), three);
  {
    torch::NoGradGuard no_grad;
    for (size_t i = 0; i < full->parameters().size(); ++i)
      nested->parameters()[i].copy_(full->parameters()[i]);
  }
  full->train();
  nested->train();
  at::Generator gen = MakeGenerator(3);
  const torch::Tensor h = torch::randn({3, 5, 6, 3});
  const auto z = NestedLatents(3, per_part, 3, gen);
  const torch::Tensor weights =
      torch::randn({3 * 12, 15, 6, 3});  // a loss that weighs every sample
  const torch::Tensor a = full->forward(h, z), b = nested->ForwardNested(h, z, per_part);
  CHECK(torch::allclose(a, b, 1e-5, 1e-5));
  (a * weights).sum().backward();
  (b * weights).sum().backward();
  // Tolerance: relative to the largest gradient of all (the convs' biases before a batch norm
  // get gradients that are zero up to rounding, which the two orders of summation round apart).
  double scale = 0;
  for (const auto& p : full->parameters())
    scale = std::max(scale, p.grad().abs().max().item<double>());
  const auto named = full->named_parameters();
  for (size_t i = 0; i < full->parameters().size(); ++i) {
    INFO(named[i].key());
    const torch::Tensor ga = full->parameters()[i].grad(), gb = nested->parameters()[i].grad();
    REQUIRE(gb.defined());
    CHECK(torch::allclose(ga, gb, 1e-4, 1e-5 * scale));
  }
  for (size_t i = 0; i < full->buffers().size(); ++i) {
    CHECK(torch::allclose(full->buffers()[i], nested->buffers()[i], 1e-5, 1e-6));
  }
  // Latents that are not nested as per_part says are refused.
  std::vector<torch::Tensor> flat = {torch::randn({36, 3}), z[1], z[2]};
  CHECK_THROWS_WITH(nested->ForwardNested(h, flat, per_part),
                    Catch::Contains("latent 0 is not nested"));
  CHECK_THROWS_WITH(nested->ForwardNested(h, z, {2, 3}), Catch::Contains("expected 3 latents"));
  CHECK_THROWS_WITH(nested->ForwardNested(h, z, {2, 0, 2}), Catch::Contains("must be >= 1, got 0"));
}
