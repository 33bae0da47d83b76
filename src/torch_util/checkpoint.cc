#include "torch_util/checkpoint.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/file_util.h"

namespace motionfork {

namespace fs = std::filesystem;

namespace {

template <typename T>
std::string Serialize(T& obj) {
  torch::serialize::OutputArchive archive;
  obj.save(archive);
  std::ostringstream s;
  archive.save_to(s);
  return s.str();
}

template <typename T>
void Deserialize(T& obj, const fs::path& path) {
  torch::serialize::InputArchive archive;
  archive.load_from(path.string());
  obj.load(archive);
}

}  // namespace

void SaveCheckpoint(const std::string& dir, const std::string& weights_name,
                    torch::nn::Module& module, torch::optim::Optimizer& optimizer, int epochs_done,
                    const std::vector<std::pair<std::string, std::string>>& extra_files) {
  std::ostringstream state;
  torch::save(torch::tensor(static_cast<int64_t>(epochs_done)), state);
  std::vector<NamedBytes> files = {{weights_name, Serialize(module)},
                                   {"optimizer.pt", Serialize(optimizer)},
                                   {"state.pt", state.str()}};
  for (const auto& [name, bytes] : extra_files) files.push_back({name, bytes});
  WriteFileSet(dir, files);
}

int LoadCheckpoint(const std::string& dir, const std::string& weights_name,
                   torch::nn::Module& module, torch::optim::Optimizer& optimizer) {
  const fs::path d(dir);
  RecoverFileSets(dir);
  if (!fs::is_regular_file(d / "state.pt")) return 0;
  torch::Tensor epochs;
  torch::load(epochs, (d / "state.pt").string());
  Deserialize(module, d / weights_name);
  Deserialize(optimizer, d / "optimizer.pt");
  return static_cast<int>(epochs.item<int64_t>());
}

}  // namespace motionfork
