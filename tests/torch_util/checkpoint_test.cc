// Training checkpoints written as one set: a write killed half-way is rolled back when training
// resumes, and the epoch log never keeps a row without its checkpoint.
#include "torch_util/checkpoint.h"

#include <torch/torch.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "io/file_util.h"
#include "test_support.h"
#include "torch_util/training_loop.h"

namespace motionfork {
namespace {

namespace fs = std::filesystem;

TEST_CASE("checkpoint: a killed write is rolled back on resume, the log cut to the checkpoint") {
  testing::TempDir dir;
  const fs::path ckpt = dir.path() / "checkpoint", log = dir.path() / "log.csv";
  torch::manual_seed(0);
  torch::nn::Linear net(3, 2);
  torch::optim::Adam adam(net->parameters(), torch::optim::AdamOptions(0.1));
  SaveCheckpoint(ckpt.string(), "w.pt", *net, adam, 1, {{"extra.txt", "1"}});
  const std::string weights_1 = ReadFileBytes((ckpt / "w.pt").string());
  AppendEpochLog(log, "lr", 0, 0.1, 1.0, {{"loss", 2.0}});
  // Epoch 2: its log row is appended, then the checkpoint write is killed after the new weights
  // moved in (the old set aside in the temporary folder, the rest not yet installed).
  AppendEpochLog(log, "lr", 1, 0.1, 1.0, {{"loss", 1.5}});
  const fs::path temp = ckpt / ".w.pt.tmp4999999";
  fs::create_directories(temp / "old");
  fs::create_directories(temp / "new");
  std::ofstream(temp / "names") << "w.pt\noptimizer.pt\nstate.pt\nextra.txt\n";
  for (const char* name : {"w.pt", "optimizer.pt", "state.pt", "extra.txt"}) {
    fs::rename(ckpt / name, temp / "old" / name);
    std::ofstream(temp / "new" / name) << "epoch 2";
  }
  fs::rename(temp / "new" / "w.pt", ckpt / "w.pt");

  torch::nn::Linear again(3, 2);
  torch::optim::Adam adam_again(again->parameters(), torch::optim::AdamOptions(0.1));
  CHECK(ResumeFromCheckpoint(ckpt, "w.pt", *again, adam_again, log) == 1);
  CHECK(ReadFileBytes((ckpt / "w.pt").string()) == weights_1);
  CHECK(ReadFileBytes((ckpt / "extra.txt").string()) == "1");
  CHECK_FALSE(fs::exists(temp));
  CHECK(torch::equal(again->weight, net->weight));
  const std::string rows = ReadFileBytes(log.string());
  CHECK(rows == "epoch,lr,seconds,loss\n1,0.1,1,2\n");
}

TEST_CASE("checkpoint: a new checkpoint replaces every file of the old one") {
  testing::TempDir dir;
  const std::string ckpt = dir.file("checkpoint");
  torch::nn::Linear net(3, 2);
  torch::optim::Adam adam(net->parameters(), torch::optim::AdamOptions(0.1));
  SaveCheckpoint(ckpt, "w.pt", *net, adam, 1);
  SaveCheckpoint(ckpt, "w.pt", *net, adam, 2);
  torch::nn::Linear again(3, 2);
  torch::optim::Adam adam_again(again->parameters(), torch::optim::AdamOptions(0.1));
  CHECK(LoadCheckpoint(ckpt, "w.pt", *again, adam_again) == 2);
  int entries = 0;
  for (const auto& e : fs::directory_iterator(ckpt)) entries += e.is_regular_file() ? 1 : 100;
  CHECK(entries == 3);  // w.pt, optimizer.pt, state.pt; no temporary folder
}

}  // namespace
}  // namespace motionfork
