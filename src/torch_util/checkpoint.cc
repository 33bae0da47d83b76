#include "torch_util/checkpoint.h"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace motionfork {

namespace fs = std::filesystem;

namespace {

// Temporary file + rename (torch_util does not depend on io/).
void WriteAtomically(const fs::path& path, const std::string& bytes) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << bytes;
    if (!out.flush()) throw std::runtime_error("cannot write " + tmp.string());
  }
  fs::rename(tmp, path);
}

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
                    torch::nn::Module& module, torch::optim::Optimizer& optimizer,
                    int epochs_done) {
  const fs::path d(dir);
  fs::create_directories(d);
  WriteAtomically(d / weights_name, Serialize(module));
  WriteAtomically(d / "optimizer.pt", Serialize(optimizer));
  std::ostringstream state;
  torch::save(torch::tensor(static_cast<int64_t>(epochs_done)), state);
  WriteAtomically(d / "state.pt", state.str());
}

int LoadCheckpoint(const std::string& dir, const std::string& weights_name,
                   torch::nn::Module& module, torch::optim::Optimizer& optimizer) {
  const fs::path d(dir);
  if (!fs::is_regular_file(d / "state.pt")) return 0;
  torch::Tensor epochs;
  torch::load(epochs, (d / "state.pt").string());
  Deserialize(module, d / weights_name);
  Deserialize(optimizer, d / "optimizer.pt");
  return static_cast<int>(epochs.item<int64_t>());
}

}  // namespace motionfork
