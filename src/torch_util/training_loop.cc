#include "torch_util/training_loop.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include "io/file_util.h"
#include "torch_util/checkpoint.h"

namespace motionfork {

namespace fs = std::filesystem;

int ResumeFromCheckpoint(const fs::path& ckpt_dir, const std::string& weights_name,
                         torch::nn::Module& module, torch::optim::Optimizer& optimizer,
                         const fs::path& epoch_log) {
  fs::create_directories(ckpt_dir);
  const int epochs_done = LoadCheckpoint(ckpt_dir.string(), weights_name, module, optimizer);
  TrimEpochLog(epoch_log, epochs_done);
  return epochs_done;
}

int ResumeTraining(const fs::path& ckpt_dir, const std::string& weights_name,
                   torch::nn::Module& module, torch::optim::Optimizer& optimizer,
                   const fs::path& epoch_log,
                   const std::function<void(const std::string&)>& message) {
  const int epochs_done =
      ResumeFromCheckpoint(ckpt_dir, weights_name, module, optimizer, epoch_log);
  if (epochs_done > 0 && message) {
    message("resuming from " + ckpt_dir.string() + " after epoch " + std::to_string(epochs_done));
  }
  return epochs_done;
}

void RequireFiniteLoss(double loss, const std::string& what, int epoch) {
  if (!std::isfinite(loss)) {
    throw std::runtime_error(what + ": the loss became non-finite at epoch " +
                             std::to_string(epoch + 1));
  }
}

void SetLearningRate(torch::optim::Adam& adam, double lr) {
  for (auto& group : adam.param_groups())
    static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
}

double AnnealedWeight(double start, int epochs, double progress) {
  if (epochs <= 0) return 1.0;
  return start + (1.0 - start) * std::min(1.0, progress / epochs);
}

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void TrimEpochLog(const fs::path& file, int epochs_done) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return;
  const std::string text = ReadFileBytes(file.string());
  std::string kept;
  bool header = true, cut = false;
  for (size_t begin = 0; begin < text.size();) {
    size_t end = text.find('\n', begin);
    end = end == std::string::npos ? text.size() : end + 1;
    const std::string line = text.substr(begin, end - begin);
    begin = end;
    // Rows start with their 1-based epoch; the header does not.
    if (!header && std::atol(line.c_str()) > epochs_done) {
      cut = true;
      continue;
    }
    header = false;
    kept += line;
  }
  if (cut) WriteFileAtomically(file.string(), kept);
}

void AppendEpochLog(const fs::path& file, const std::string& column, int epoch, double value,
                    double seconds, const std::vector<std::pair<std::string, double>>& terms) {
  const bool fresh = !fs::exists(file);
  std::ofstream csv(file, std::ios::app);
  if (fresh) {
    csv << "epoch," << column << ",seconds";
    for (const auto& kv : terms) csv << "," << kv.first;
    csv << "\n";
  }
  csv << epoch + 1 << "," << value << "," << seconds;
  for (const auto& kv : terms) csv << "," << kv.second;
  csv << "\n";
}

}  // namespace motionfork
