#include "app_common.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace motionfork::app {

std::string ConfigDir(const std::string& flag_value) {
  if (!flag_value.empty()) return flag_value;
  if (const char* env = std::getenv("MOTIONFORK_CONFIG_DIR"); env && *env) return env;
  // The source tree's configs for a build used in place; the installed ones for `cmake --install`
  // (the tree may be gone).
  if (std::filesystem::is_directory(MOTIONFORK_CONFIG_DIR)) return MOTIONFORK_CONFIG_DIR;
  if (std::filesystem::is_directory(MOTIONFORK_INSTALLED_CONFIG_DIR)) {
    return MOTIONFORK_INSTALLED_CONFIG_DIR;
  }
  return MOTIONFORK_CONFIG_DIR;
}

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)),
      enabled_(enabled),
      tty_(isatty(fileno(stderr))),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

ProgressBar::~ProgressBar() { Finish(); }

void ProgressBar::Update(double fraction, const std::string& detail) {
  if (!enabled_ || finished_) return;
  fraction = std::min(1.0, std::max(0.0, fraction));
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (!tty_) {
    const int decile = static_cast<int>(fraction * 10);
    if (decile == last_decile_) return;
    last_decile_ = decile;
    std::fprintf(stderr, "%s: %3d%% (%s)%s%s\n", label_.c_str(), decile * 10,
                 Duration(elapsed).c_str(), detail.empty() ? "" : " ", detail.c_str());
    return;
  }
  if (now - last_draw_ < std::chrono::milliseconds(100) && fraction < 1.0) return;
  last_draw_ = now;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(fraction * kWidth);
  std::string bar(filled, '#');
  bar += std::string(kWidth - filled, '.');
  std::string eta;
  if (fraction > 0.02 && fraction < 1.0)
    eta = ", " + Duration(elapsed / fraction - elapsed) + " left";
  std::string d = detail.size() > 110 ? "..." + detail.substr(detail.size() - 107) : detail;
  std::fprintf(stderr, "\r\033[K%s [%s] %3d%% %s%s %s", label_.c_str(), bar.c_str(),
               static_cast<int>(fraction * 100), Duration(elapsed).c_str(), eta.c_str(), d.c_str());
  std::fflush(stderr);
}

void ProgressBar::Finish() {
  if (!enabled_ || finished_) return;
  finished_ = true;
  if (tty_ && last_draw_ > start_) std::fprintf(stderr, "\n");
}

StageProgress StageBars::Callback() {
  return [this](const std::string& stage, double fraction, const std::string& detail) {
    if (stage == kWarningStage) return PrintWarning(detail);
    if (!bar_ || stage != stage_) {
      bar_ = std::make_unique<ProgressBar>(stage, enabled_);
      stage_ = stage;
    }
    bar_->Update(fraction, detail);
  };
}

void EpochBars::Update(int epoch, double fraction, const std::string& detail) {
  if (!bar_) {
    bar_ = std::make_unique<ProgressBar>(
        "epoch " + std::to_string(epoch + 1) + "/" + std::to_string(epochs_), enabled_);
  }
  bar_->Update(fraction, detail);
}

void EpochBars::PrintEpoch(int epoch, double seconds,
                           const std::vector<std::pair<std::string, double>>& terms, int digits,
                           std::optional<double> kl_weight) {
  bar_.reset();
  std::printf("epoch %d/%d (%s", epoch + 1, epochs_, Duration(seconds).c_str());
  if (kl_weight) std::printf(", kl weight %.3g", *kl_weight);
  std::printf("):");
  for (const auto& [name, v] : terms) std::printf(" %s %.*g", name.c_str(), digits, v);
  std::printf("\n");
  std::fflush(stdout);
}

void PrintMessage(const std::string& message) {
  std::printf("%s\n", message.c_str());
  std::fflush(stdout);  // in order with what worker processes print
}

void PrintText(const std::string& text) { std::fputs(text.c_str(), stdout); }

void PrintWarning(const std::string& message) {
  std::fprintf(stderr, "%smotionfork: warning: %s\n", isatty(2) ? "\r\033[K" : "", message.c_str());
}

}  // namespace motionfork::app
