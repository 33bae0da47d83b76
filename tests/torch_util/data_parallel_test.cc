// DataParallel over real c10d (TCPStore + Gloo on 127.0.0.1): two workers as two threads of this
// process, each with its own store client and process group, as two processes would have.
#include "torch_util/data_parallel.h"

#include <catch2/catch.hpp>
#include <functional>
#include <future>
#include <mutex>
#include <string>
#include <thread>

#include "launch/worker_launcher.h"
#include "launch/worker_place.h"

using Catch::Contains;
using motionfork::DataParallel;
using motionfork::WorkerPlace;

namespace {

WorkerPlace Place(int rank, int world, int port) {
  WorkerPlace p;
  p.rank = rank;
  p.world_size = world;
  p.local_rank = rank;
  p.local_world_size = world;
  p.master_addr = "127.0.0.1";
  p.master_port = port;
  return p;
}

// Runs body(workers) on ranks 0..world-1 at once, one thread each; rethrows a rank's failure.
void OnWorkers(int world, const std::function<void(DataParallel&)>& body) {
  const int port = motionfork::FreeLocalPort();
  std::vector<std::future<void>> done;
  for (int r = 0; r < world; ++r) {
    done.push_back(std::async(std::launch::async, [=, &body] {
      DataParallel workers(Place(r, world, port), std::chrono::seconds(20),
                           std::chrono::seconds(20));
      body(workers);
      workers.Barrier();  // no worker leaves while another still talks to it
    }));
  }
  for (auto& d : done) d.get();
}

}  // namespace

TEST_CASE("one worker: collectives are local and the step is the plain optimiser step") {
  DataParallel one;
  CHECK_FALSE(one.distributed());
  CHECK(one.writes());
  CHECK(one.BatchShare(7).begin == 0);
  CHECK(one.BatchShare(7).end == 7);
  torch::Tensor w = torch::ones({3}, torch::requires_grad());
  torch::optim::SGD sgd({w}, torch::optim::SGDOptions(0.5));
  motionfork::DataParallelStep(one, sgd, (w * w).sum(), {w}, 1.0, 0);
  CHECK(torch::allclose(w, torch::zeros({3})));  // 1 - 0.5 * 2
  std::vector<double> v = {1.5};
  one.SumValues(&v);
  CHECK(v[0] == 1.5);
}

TEST_CASE("gradients are summed over workers, weighted by their shares, in many buckets") {
  OnWorkers(2, [](DataParallel& workers) {
    workers.set_bucket_bytes(64);  // several buckets: a float tensor of 40 values is one alone
    const double r = workers.rank();
    torch::Tensor a = torch::zeros({40}, torch::requires_grad());
    torch::Tensor b = torch::zeros({3, 2}, torch::requires_grad());
    torch::Tensor unused = torch::zeros({5}, torch::requires_grad());
    torch::Tensor d = torch::zeros({2}, torch::dtype(torch::kFloat64).requires_grad(true));
    const torch::Tensor loss =
        (a * (r + 1)).sum() + (b * (10 * (r + 1))).sum() + (d * (100 * (r + 1))).sum();
    loss.backward();
    // Rank 0 holds 1 of 4 items, rank 1 the other 3.
    workers.ReduceGradients({a, b, unused, d}, r == 0 ? 0.25 : 0.75);
    CHECK(torch::allclose(a.grad(), torch::full({40}, 0.25 * 1 + 0.75 * 2)));
    CHECK(torch::allclose(b.grad(), torch::full({3, 2}, 0.25 * 10 + 0.75 * 20)));
    CHECK(torch::allclose(unused.grad(), torch::zeros({5})));
    CHECK(torch::allclose(d.grad(), torch::full({2}, 0.25 * 100 + 0.75 * 200, torch::kFloat64)));
    CHECK(workers.reduce_calls() == 1);
  });
}

TEST_CASE("rank 0's training state reaches every worker, buffers are averaged, counts copied") {
  OnWorkers(2, [](DataParallel& workers) {
    torch::manual_seed(workers.rank() + 1);  // different weights on each worker
    torch::nn::Sequential net(torch::nn::Linear(3, 4), torch::nn::BatchNorm1d(4));
    torch::optim::Adam adam(net->parameters(), torch::optim::AdamOptions(0.1));
    net->train();
    net->forward(torch::randn({8, 3}) * (workers.rank() + 1)).sum().backward();
    adam.step();  // Adam's state exists on both
    std::vector<double> values = {workers.rank() == 0 ? 7.0 : -1.0};
    workers.BroadcastTrainingState(*net, adam, &values);
    CHECK(values == std::vector<double>{7.0});
    // Weights now equal everywhere: the sum over workers is world x rank 0's.
    for (const torch::Tensor& p : net->parameters()) {
      std::vector<double> mine = {p.sum().item<double>()}, all = mine;
      workers.SumValues(&all);
      CHECK(all[0] == Approx(2 * mine[0]).epsilon(1e-6));
    }
    // Batch-norm running statistics differ per worker; after AverageBuffers they agree.
    net->forward(torch::randn({8, 3}) * (workers.rank() + 1));
    workers.AverageBuffers(*net);
    for (const torch::Tensor& b : net->buffers()) {
      std::vector<double> mine = {b.to(torch::kFloat64).sum().item<double>()}, all = mine;
      workers.SumValues(&all);
      CHECK(all[0] == Approx(2 * mine[0]).epsilon(1e-6));
    }
  });
}

TEST_CASE("a worker that stops makes the other's next collective fail, naming its rank") {
  const int port = motionfork::FreeLocalPort();
  std::promise<void> rank1_gone;
  auto rank1 = std::async(std::launch::async, [&] {
    {
      DataParallel workers(Place(1, 2, port), std::chrono::seconds(20), std::chrono::seconds(20));
      workers.Barrier();
    }  // its connections close, as when a process dies
    rank1_gone.set_value();
  });
  DataParallel workers(Place(0, 2, port), std::chrono::seconds(20), std::chrono::seconds(20));
  workers.Barrier();
  rank1.get();
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> v = {1};
  REQUIRE_THROWS_WITH(workers.SumValues(&v),
                      Contains("worker rank 0 of 2") && Contains("rank 1 stopped"));
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(60));
}

TEST_CASE("sums of any size agree to the bit on every worker, three workers, sizes interleaved") {
  // Small sums run on Gloo's synchronous pairs, one algorithm per size; a large one goes through
  // the process group. Three workers: halving-doubling's non-power-of-two case.
  const size_t large = DataParallel::kSmallSumBytes / sizeof(double) + 1;
  std::vector<std::vector<double>> results(3);
  std::mutex m;
  OnWorkers(3, [&](DataParallel& workers) {
    const int r = workers.rank();
    std::vector<double> all;
    for (const size_t n : {size_t{3}, size_t{8192}, size_t{3}, large, size_t{8192}, size_t{1}}) {
      std::vector<double> v(n);
      for (size_t i = 0; i < n; ++i) v[i] = 0.1 * (r + 1) + 1e-3 * static_cast<double>(i % 97);
      workers.SumValues(&v);
      for (size_t i = 0; i < n; i += 1 + n / 50) {
        CHECK(v[i] == Approx(0.6 + 3e-3 * static_cast<double>(i % 97)).epsilon(1e-12));
      }
      all.insert(all.end(), v.begin(), v.end());
    }
    std::lock_guard<std::mutex> lock(m);
    results[r] = all;
  });
  CHECK(results[0] == results[1]);
  CHECK(results[0] == results[2]);
}

TEST_CASE("a worker that never arrives makes a small sum fail within the timeout, not hang") {
  const int port = motionfork::FreeLocalPort();
  std::promise<void> rank0_failed;
  auto rank1 = std::async(std::launch::async, [&] {
    DataParallel workers(Place(1, 2, port), std::chrono::seconds(2), std::chrono::seconds(20));
    workers.Barrier();
    rank0_failed.get_future().wait();  // alive (its heartbeat goes on) but silent
  });
  DataParallel workers(Place(0, 2, port), std::chrono::seconds(2), std::chrono::seconds(20));
  workers.Barrier();
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> v(100, 1.0);
  CHECK_THROWS_WITH(workers.SumValues(&v, "batch statistics"),
                    Contains("worker rank 0 of 2") && Contains("batch statistics failed"));
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(20));
  rank0_failed.set_value();
  rank1.get();
}

TEST_CASE("a rendezvous short of WORLD_SIZE or without a master is a clear error") {
  const int port = motionfork::FreeLocalPort();
  // Rank 0 alone of three.
  REQUIRE_THROWS_WITH(
      DataParallel(Place(0, 3, port), std::chrono::seconds(2), std::chrono::seconds(2)),
      Contains("only 1 of WORLD_SIZE=3 workers reached 127.0.0.1:" + std::to_string(port)));
  // Nobody serves the store.
  REQUIRE_THROWS_WITH(DataParallel(Place(1, 2, motionfork::FreeLocalPort()),
                                   std::chrono::seconds(2), std::chrono::seconds(2)),
                      Contains("cannot reach the master (rank 0) at 127.0.0.1:"));
}
