#include "torch_util/data_parallel.h"

#include "launch/worker_place.h"
#include "torch_util/threads.h"

// Debian's LibTorch is built with Gloo; its header declares ProcessGroupGloo only under this macro.
#ifndef USE_C10D_GLOO
#define USE_C10D_GLOO 1
#endif
#include <gloo/algorithm.h>
#include <gloo/allreduce_halving_doubling.h>
#include <gloo/rendezvous/context.h>
#include <gloo/transport/device.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <torch/csrc/distributed/c10d/PrefixStore.hpp>
#include <torch/csrc/distributed/c10d/ProcessGroupGloo.hpp>
#include <torch/csrc/distributed/c10d/TCPStore.hpp>

namespace motionfork {

namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

constexpr const char* kKeyPrefix = "motionfork/";
constexpr auto kHeartbeatPeriod = std::chrono::seconds(1);
constexpr auto kHeartbeatWindow = std::chrono::seconds(3);

std::string Seconds(milliseconds t) {
  std::ostringstream s;
  s << t.count() / 1000.0 << " s";
  return s.str();
}

std::string Key(const std::string& name) { return kKeyPrefix + name; }

int64_t ReadCounter(c10d::Store& store, const std::string& key) { return store.add(key, 0); }

// Tensors grouped into runs of one dtype of at most `bytes` each (a tensor larger than `bytes`
// gets a bucket of its own).
std::vector<std::vector<torch::Tensor>> Buckets(const std::vector<torch::Tensor>& tensors,
                                                int64_t bytes) {
  std::vector<std::vector<torch::Tensor>> buckets;
  int64_t filled = 0;
  for (const torch::Tensor& t : tensors) {
    const int64_t size = t.numel() * static_cast<int64_t>(t.element_size());
    if (buckets.empty() || filled + size > bytes ||
        buckets.back().front().scalar_type() != t.scalar_type()) {
      buckets.emplace_back();
      filled = 0;
    }
    buckets.back().push_back(t);
    filled += size;
  }
  return buckets;
}

torch::Tensor Flatten(const std::vector<torch::Tensor>& tensors) {
  std::vector<torch::Tensor> flat;
  for (const torch::Tensor& t : tensors) flat.push_back(t.detach().reshape({-1}));
  return torch::cat(flat);
}

void Unflatten(const torch::Tensor& flat, const std::vector<torch::Tensor>& tensors) {
  int64_t offset = 0;
  torch::NoGradGuard no_grad;
  for (const torch::Tensor& t : tensors) {
    t.copy_(flat.narrow(0, offset, t.numel()).view_as(t));
    offset += t.numel();
  }
}

}  // namespace

// A sum of a fixed number of doubles over the workers, run on the calling thread (Gloo's
// halving-doubling all-reduce on synchronous pairs): its buffer and the algorithm bound to it.
struct SmallSum {
  std::vector<double> values;
  std::unique_ptr<gloo::Algorithm> algorithm;
};

struct DataParallel::Group {
  c10::intrusive_ptr<c10d::TCPStore> store;
  c10::intrusive_ptr<c10d::ProcessGroupGloo> gloo;
  // Gloo's own context with its pairs in synchronous mode, for small sums (SumValues): the
  // calling thread sends and receives itself. ProcessGroupGloo queues every collective to its
  // worker thread and receives through Gloo's event-loop thread; those hand-offs cost 1-2 ms a
  // sum on a busy 2-core machine, where the sum itself takes under 0.1 ms.
  std::shared_ptr<gloo::rendezvous::Context> small;
  std::map<size_t, SmallSum> small_sums;  // by number of values, created in call order
  std::atomic<bool> stop{false};
  std::thread heartbeat;
  milliseconds timeout{60000};

  // A new client connection to the store (the heartbeat and the diagnosis of a failure use their
  // own, so that they never wait behind each other).
  c10::intrusive_ptr<c10d::TCPStore> Client(const WorkerPlace& p, milliseconds t) const {
    c10d::TCPStoreOptions o;
    o.port = static_cast<uint16_t>(p.master_port);
    o.isServer = false;
    o.waitWorkers = false;
    o.timeout = t;
    return c10::make_intrusive<c10d::TCPStore>(p.master_addr, o);
  }

  ~Group() {
    stop = true;
    if (heartbeat.joinable()) heartbeat.join();
  }
};

DataParallel::DataParallel() = default;

DataParallel::DataParallel(const WorkerPlace& place, milliseconds timeout,
                           milliseconds join_timeout)
    : rank_(place.rank),
      world_size_(place.world_size),
      local_world_size_(place.local_world_size),
      place_(std::make_unique<WorkerPlace>(place)) {
  if (place.world_size <= 1) return;
  group_ = std::make_unique<Group>();
  group_->timeout = timeout;
  const std::string where = place.master_addr + ":" + std::to_string(place.master_port);
  const std::string who =
      "worker rank " + std::to_string(place.rank) + " of " + std::to_string(place.world_size);
  c10d::TCPStoreOptions o;
  o.port = static_cast<uint16_t>(place.master_port);
  o.isServer = place.rank == 0;
  o.waitWorkers = false;
  o.timeout = join_timeout;  // rank 0 serves the store once it has loaded its data
  try {
    group_->store = c10::make_intrusive<c10d::TCPStore>(place.master_addr, o);
  } catch (const std::exception& e) {
    throw std::runtime_error(
        who + ": " +
        (place.rank == 0 ? "cannot serve the rendezvous at " + where + " (MASTER_ADDR, MASTER_PORT)"
                         : "cannot reach the master (rank 0) at " + where + " within " +
                               Seconds(join_timeout) + " (MASTER_ADDR, MASTER_PORT)") +
        ": " + e.what());
  }
  c10d::Store& store = *group_->store;
  if (store.add(Key("rank/" + std::to_string(place.rank)), 1) > 1) {
    throw std::runtime_error(who + ": another worker joined " + where + " as RANK " +
                             std::to_string(place.rank) + " (each worker needs its own RANK)");
  }
  const std::string world_key = Key("world_size");
  if (place.rank == 0) {
    const std::string w = std::to_string(place.world_size);
    store.set(world_key, std::vector<uint8_t>(w.begin(), w.end()));
  }
  store.add(Key("joined"), 1);
  const auto deadline = Clock::now() + join_timeout;
  int64_t joined = 0;
  while ((joined = ReadCounter(store, Key("joined"))) < place.world_size) {
    if (Clock::now() > deadline) {
      throw std::runtime_error(who + ": only " + std::to_string(joined) +
                               " of WORLD_SIZE=" + std::to_string(place.world_size) +
                               " workers reached " + where + " within " + Seconds(join_timeout) +
                               " (is WORLD_SIZE right, and was every worker started?)");
    }
    std::this_thread::sleep_for(milliseconds(50));
  }
  if (joined > place.world_size) {
    throw std::runtime_error(who + ": " + std::to_string(joined) + " workers joined " + where +
                             ", WORLD_SIZE is " + std::to_string(place.world_size) +
                             " (the workers disagree on WORLD_SIZE)");
  }
  if (place.rank != 0) {
    const std::vector<uint8_t> w = store.get(world_key);
    const std::string theirs(w.begin(), w.end());
    if (theirs != std::to_string(place.world_size)) {
      throw std::runtime_error(who + ": WORLD_SIZE is " + std::to_string(place.world_size) +
                               " here but " + theirs + " on rank 0");
    }
  }
  auto options = c10d::ProcessGroupGloo::Options::create(timeout);
  const char* ifname = std::getenv("GLOO_SOCKET_IFNAME");
  std::shared_ptr<gloo::transport::Device> device;
  if (ifname && *ifname) {
    device = c10d::ProcessGroupGloo::createDeviceForInterface(ifname);
  } else if (place.master_addr == "127.0.0.1" || place.master_addr == "localhost") {
    device = c10d::ProcessGroupGloo::createDeviceForHostname("127.0.0.1");
  } else {
    device = c10d::ProcessGroupGloo::createDefaultDevice();
  }
  options->devices.push_back(device);
  options->threads = 1;
  try {
    group_->gloo = c10::make_intrusive<c10d::ProcessGroupGloo>(
        c10::make_intrusive<c10d::PrefixStore>("gloo", group_->store), place.rank, place.world_size,
        options);
    group_->small = std::make_shared<gloo::rendezvous::Context>(place.rank, place.world_size);
    group_->small->setTimeout(timeout);
    c10d::ProcessGroupGloo::GlooStore small_store(
        c10::make_intrusive<c10d::PrefixStore>("gloo-small", group_->store));
    group_->small->connectFullMesh(small_store, device);
    for (int r = 0; r < place.world_size; ++r) {
      if (r != place.rank) group_->small->getPair(r)->setSync(true, false);
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(who + ": the Gloo process group did not connect: " + e.what());
  }
  Group* g = group_.get();
  g->heartbeat = std::thread([g, place] {
    try {
      auto client = g->Client(place, milliseconds(5000));
      const std::string key = Key("heartbeat/" + std::to_string(place.rank));
      while (!g->stop) {
        client->add(key, 1);
        for (auto t = milliseconds(0); t < kHeartbeatPeriod && !g->stop; t += milliseconds(100))
          std::this_thread::sleep_for(milliseconds(100));
      }
    } catch (const std::exception&) {
      // The store is gone (rank 0 stopped): the next collective reports it.
    }
  });
  // Every collective waits for the other workers' communication threads: let them run at once.
  ShortenHelperThreadSlices();
}

DataParallel::~DataParallel() = default;

template <typename F>
void DataParallel::Collective(const char* what, F&& run) {
  if (!group_) return;
  try {
    run(*group_->gloo);
    return;
  } catch (const std::exception& e) {
    // Which workers stopped: those whose heartbeat did not move for a few seconds; the store
    // itself gone means rank 0 (which holds it) stopped.
    std::string stopped;
    try {
      auto client = group_->Client(*place_, milliseconds(5000));
      std::vector<int64_t> before(world_size_), after(world_size_);
      for (int r = 0; r < world_size_; ++r)
        before[r] = ReadCounter(*client, Key("heartbeat/" + std::to_string(r)));
      std::this_thread::sleep_for(kHeartbeatWindow);
      for (int r = 0; r < world_size_; ++r) {
        after[r] = ReadCounter(*client, Key("heartbeat/" + std::to_string(r)));
        if (r != rank_ && after[r] == before[r])
          stopped += (stopped.empty() ? "rank " : ", rank ") + std::to_string(r);
      }
      if (rank_ == 0) std::this_thread::sleep_for(kHeartbeatWindow);  // others read too
    } catch (const std::exception&) {
      if (rank_ != 0) stopped = "rank 0 (the master, which holds the rendezvous store)";
    }
    group_->stop = true;
    throw std::runtime_error("worker rank " + std::to_string(rank_) + " of " +
                             std::to_string(world_size_) + ": the " + what + " failed: " +
                             (stopped.empty()
                                  ? std::string("a worker stopped or the network failed")
                                  : stopped + " stopped") +
                             "; stopping (" + e.what() + ")");
  }
}

Share DataParallel::BatchShare(int64_t n) const { return ShareOf(n, rank_, world_size_); }

void DataParallel::RequireBatch(int64_t batch, const std::string& key) const {
  if (batch < world_size()) {
    throw std::invalid_argument(key + ": expected at least one item a step for each of the " +
                                std::to_string(world_size()) + " workers, found " +
                                std::to_string(batch));
  }
}

int DataParallel::ThreadsPerWorker(int requested) const {
  const int cap = std::max(1, CoresAvailable() / std::max(1, local_world_size_));
  return std::max(1, std::min(requested, cap));
}

void DataParallel::ReduceGradients(const std::vector<torch::Tensor>& params, double weight) {
  if (!distributed()) return;
  const auto start = Clock::now();
  std::vector<torch::Tensor> grads;
  for (const torch::Tensor& p : params) {
    torch::Tensor& g = const_cast<torch::Tensor&>(p).mutable_grad();
    if (!g.defined()) g = torch::zeros_like(p);
    grads.push_back(g);
  }
  const auto buckets = Buckets(grads, bucket_bytes_);
  std::vector<torch::Tensor> flats;
  for (const auto& b : buckets) flats.push_back(Flatten(b).mul_(weight));
  Collective("gradient all-reduce", [&](c10d::ProcessGroupGloo& gloo) {
    std::vector<c10::intrusive_ptr<c10d::Work>> works;
    std::vector<std::vector<at::Tensor>> args;
    args.reserve(flats.size());
    for (const torch::Tensor& f : flats) {
      args.push_back({f});
      works.push_back(gloo.allreduce(args.back()));
    }
    for (auto& w : works) w->wait();
  });
  for (size_t i = 0; i < buckets.size(); ++i) Unflatten(flats[i], buckets[i]);
  reduce_seconds_ += std::chrono::duration<double>(Clock::now() - start).count();
  ++reduce_calls_;
}

void DataParallel::BroadcastTrainingState(torch::nn::Module& module,
                                          torch::optim::Optimizer& optimizer,
                                          std::vector<double>* values) {
  if (!distributed()) return;
  std::string bytes;
  if (rank() == 0) {
    torch::serialize::OutputArchive archive, m, o;
    module.save(m);
    optimizer.save(o);
    archive.write("module", m);
    archive.write("optimizer", o);
    std::ostringstream out;
    archive.save_to(out);
    bytes = out.str();
  }
  std::vector<at::Tensor> header{torch::tensor(
      {static_cast<double>(bytes.size()), static_cast<double>(values ? values->size() : 0)},
      torch::kFloat64)};
  Collective("broadcast of the training state",
             [&](c10d::ProcessGroupGloo& gloo) { gloo.broadcast(header)->wait(); });
  const auto size = static_cast<int64_t>(header[0][0].item<double>());
  std::vector<at::Tensor> payload{torch::empty({size}, torch::kUInt8)};
  if (rank() == 0) std::memcpy(payload[0].data_ptr(), bytes.data(), bytes.size());
  std::vector<at::Tensor> numbers{
      torch::zeros({static_cast<int64_t>(header[0][1].item<double>())}, torch::kFloat64)};
  if (rank() == 0 && values) {
    for (size_t i = 0; i < values->size(); ++i) numbers[0][i] = (*values)[i];
  }
  Collective("broadcast of the training state", [&](c10d::ProcessGroupGloo& gloo) {
    gloo.broadcast(payload)->wait();
    if (numbers[0].numel() > 0) gloo.broadcast(numbers)->wait();
  });
  if (rank() != 0) {
    torch::serialize::InputArchive archive, m, o;
    archive.load_from(static_cast<const char*>(payload[0].data_ptr()), size);
    archive.read("module", m);
    archive.read("optimizer", o);
    module.load(m);
    optimizer.load(o);
    if (values) {
      values->resize(numbers[0].numel());
      for (size_t i = 0; i < values->size(); ++i) (*values)[i] = numbers[0][i].item<double>();
    }
  }
}

void DataParallel::AverageBuffers(torch::nn::Module& module) {
  if (!distributed()) return;
  std::vector<torch::Tensor> floating, counts;
  for (const torch::Tensor& b : module.buffers())
    (b.is_floating_point() ? floating : counts).push_back(b);
  for (const auto& bucket : Buckets(floating, bucket_bytes_)) {
    std::vector<at::Tensor> flat{Flatten(bucket)};
    Collective("average of the batch-norm statistics",
               [&](c10d::ProcessGroupGloo& gloo) { gloo.allreduce(flat)->wait(); });
    Unflatten(flat[0].div_(world_size()), bucket);
  }
  for (const auto& bucket : Buckets(counts, bucket_bytes_)) {
    std::vector<at::Tensor> flat{Flatten(bucket)};
    Collective("broadcast of the batch counts",
               [&](c10d::ProcessGroupGloo& gloo) { gloo.broadcast(flat)->wait(); });
    Unflatten(flat[0], bucket);
  }
}

void DataParallel::SumValues(std::vector<double>* values, const char* what) {
  if (!distributed() || values->empty()) return;
  const auto start = std::chrono::steady_clock::now();
  if (values->size() * sizeof(double) <= small_sum_bytes_) {
    // Every worker sums the same sizes in the same order, so their algorithms (and the Gloo
    // slots they take) are created in the same order.
    SmallSum& sum = group_->small_sums[values->size()];
    if (!sum.algorithm) {
      sum.values.resize(values->size());
      sum.algorithm = std::make_unique<gloo::AllreduceHalvingDoubling<double>>(
          group_->small, std::vector<double*>{sum.values.data()}, static_cast<int>(values->size()));
    }
    std::copy(values->begin(), values->end(), sum.values.begin());
    Collective(what, [&](c10d::ProcessGroupGloo&) { sum.algorithm->run(); });
    std::copy(sum.values.begin(), sum.values.end(), values->begin());
  } else {
    // The tensor shares the vector's memory: the sums land in place.
    std::vector<at::Tensor> t{
        torch::from_blob(values->data(), {static_cast<int64_t>(values->size())}, torch::kFloat64)};
    Collective(what, [&](c10d::ProcessGroupGloo& gloo) { gloo.allreduce(t)->wait(); });
  }
  sum_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++sum_calls_;
}

void DataParallel::Barrier() {
  Collective("barrier", [](c10d::ProcessGroupGloo& gloo) { gloo.barrier()->wait(); });
}

DataParallel& TrainingWorkers() {
  static std::unique_ptr<DataParallel> workers = [] {
    const WorkerPlace place = WorkerPlaceFromEnvironment();
    return place.world_size > 1
               ? std::make_unique<DataParallel>(place, DistributedTimeout(), JoinTimeout())
               : std::make_unique<DataParallel>();
  }();
  return *workers;
}

void DataParallelStep(DataParallel& workers, torch::optim::Optimizer& optimizer,
                      const torch::Tensor& loss, const std::vector<torch::Tensor>& params,
                      double weight, double grad_clip) {
  optimizer.zero_grad();
  loss.backward();
  workers.ReduceGradients(params, weight);
  if (grad_clip > 0) torch::nn::utils::clip_grad_norm_(params, grad_clip);
  optimizer.step();
}

}  // namespace motionfork
