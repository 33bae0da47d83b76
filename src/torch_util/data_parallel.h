// Data-parallel training over LibTorch's own distributed engine (c10d: a TCPStore for the
// rendezvous, ProcessGroupGloo for the collectives), shared by every trainer (generator, pose
// prior, HG-VAE, Motion-DVAE).
//
// One process per worker, placed by torchrun's environment (RANK, WORLD_SIZE, LOCAL_RANK,
// LOCAL_WORLD_SIZE, MASTER_ADDR, MASTER_PORT), so cluster launchers that start PyTorch workers
// start motionfork workers unchanged. Every worker draws the same global batch from the same
// seeded generators and keeps its contiguous share of it (ShareOf); after the backward pass the
// gradients are summed over the workers, each weighted by its share of the batch, in buckets (one
// all-reduce per bucket), so that every worker takes the same optimiser step, and the step is the
// one a single worker takes on the whole batch. Batch normalisation is the trainer's choice: the
// generator synchronises its batch statistics over the workers (SumValues forward and backward,
// generator/model/fused_ops.h: BatchSync; these small sums run on the calling thread over Gloo's
// synchronous pairs, the rest through c10d's ProcessGroupGloo); a trainer that normalises each
// worker's own share (PyTorch DDP's default) calls AverageBuffers before a bundle or checkpoint is
// written, so that the running statistics are identical on every worker.
//
// Rank 0 alone writes logs, checkpoints and bundles (writes()). A worker that dies makes the
// others' next collective fail; the error names the rank that stopped (heartbeats in the store).
#pragma once

#include <torch/torch.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace motionfork {

struct Share;        // launch/worker_place.h
struct WorkerPlace;  // launch/worker_place.h

class DataParallel {
 public:
  // One worker: every collective is a no-op.
  DataParallel();
  // Joins the run `place` describes (world_size > 1): rendezvous at MASTER_ADDR:MASTER_PORT (rank
  // 0 hosts the store), then a Gloo process group whose collectives wait at most `timeout`.
  // Throws std::runtime_error when the master cannot be reached or the workers do not all arrive
  // within `join_timeout` (workers join once they have loaded their data, which may take one
  // machine longer than another), two workers claim one rank or they disagree on WORLD_SIZE.
  DataParallel(const WorkerPlace& place, std::chrono::milliseconds timeout,
               std::chrono::milliseconds join_timeout);
  ~DataParallel();
  DataParallel(const DataParallel&) = delete;
  DataParallel& operator=(const DataParallel&) = delete;

  int rank() const { return rank_; }
  int world_size() const { return world_size_; }
  bool distributed() const { return world_size_ > 1; }
  // True on rank 0, the worker that writes logs, checkpoints and bundles.
  bool writes() const { return rank_ == 0; }
  // This worker's share of a global batch of n items.
  Share BatchShare(int64_t n) const;

  // Refuses (std::invalid_argument) a batch of fewer items than workers: `key` names the setting.
  void RequireBatch(int64_t batch, const std::string& key) const;

  // LibTorch and OpenBLAS threads for this worker: `requested`, but no more than the cores divided
  // by the workers on this machine (at least 1).
  int ThreadsPerWorker(int requested) const;

  // Gradients of `params` (undefined ones as zeros) replaced on every worker by
  // sum over workers of weight_w * grad_w: weight = this worker's share of the batch / the batch,
  // so that the result is the whole batch's gradient of a per-item mean. Buckets of at most
  // kBucketBytes (one dtype each), one all-reduce each, all in flight together.
  void ReduceGradients(const std::vector<torch::Tensor>& params, double weight);
  // Rank 0's module and optimiser state (serialised) loaded on every worker; `values` (e.g. the
  // epochs done) replaced by rank 0's.
  void BroadcastTrainingState(torch::nn::Module& module, torch::optim::Optimizer& optimizer,
                              std::vector<double>* values);
  // Floating-point buffers (batch-norm running statistics) averaged over the workers; integer
  // buffers (batch counts) copied from rank 0.
  void AverageBuffers(torch::nn::Module& module);
  // values[i] summed over the workers, in place; `what` names the sum in errors. Sums of at most
  // kSmallSumBytes (the synchronised batch statistics) run on the calling thread over Gloo's
  // synchronous pairs; larger ones through the process group.
  void SumValues(std::vector<double>* values, const char* what = "sum of the logged figures");
  // Small enough to sit in the sockets' buffers in flight (a synchronous send must not wait for
  // the peer to read).
  static constexpr size_t kSmallSumBytes = 128 << 10;
  void set_small_sum_bytes(size_t bytes) { small_sum_bytes_ = bytes; }  // benchmarks: 0 = none
  void Barrier();

  // Wall seconds spent in ReduceGradients and the number of calls (benchmarks: the all-reduce's
  // share of a step).
  double reduce_seconds() const { return reduce_seconds_; }
  // The same for SumValues (the epoch's figures and synchronised batch statistics).
  double sum_seconds() const { return sum_seconds_; }
  int64_t sum_calls() const { return sum_calls_; }
  int64_t reduce_calls() const { return reduce_calls_; }

  static constexpr int64_t kBucketBytes = 25 << 20;                // as PyTorch DDP's bucket_cap_mb
  void set_bucket_bytes(int64_t bytes) { bucket_bytes_ = bytes; }  // tests: many buckets

 private:
  struct Group;
  // Runs a collective, turning a failure into an error naming the worker(s) that stopped.
  template <typename F>
  void Collective(const char* what, F&& run);

  int rank_ = 0, world_size_ = 1, local_world_size_ = 1;
  std::unique_ptr<const WorkerPlace> place_;  // set when distributed
  std::unique_ptr<Group> group_;
  int64_t bucket_bytes_ = kBucketBytes;
  size_t small_sum_bytes_ = kSmallSumBytes;
  double reduce_seconds_ = 0, sum_seconds_ = 0;
  int64_t sum_calls_ = 0;
  int64_t reduce_calls_ = 0;
};

// The run this process belongs to, joined on first use from WorkerPlaceFromEnvironment() (one
// worker when the environment names none), as torch.distributed's default group.
DataParallel& TrainingWorkers();

// The training step every trainer takes: gradients cleared, loss back-propagated, gradients
// reduced over the workers (weight: this worker's share of the batch), the gradient norm over
// params clipped to grad_clip (<= 0: no clipping), one step of optimizer.
void DataParallelStep(DataParallel& workers, torch::optim::Optimizer& optimizer,
                      const torch::Tensor& loss, const std::vector<torch::Tensor>& params,
                      double weight, double grad_clip);

}  // namespace motionfork
