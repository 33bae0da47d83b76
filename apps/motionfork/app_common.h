// Shared pieces of the motionfork subcommands: where configs and caches live, a progress bar,
// and number formatting. Only apps print; libraries report through callbacks.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/progress.h"
#include "core/text_format.h"
#include "io/cache_dir.h"  // CacheDir: --cache-dir, else the environment's

namespace motionfork::app {

// Exit statuses shared by every subcommand.
constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;

// --config-dir, else $MOTIONFORK_CONFIG_DIR, else the source tree's configs/ when it exists, else
// the installed configs (<prefix>/share/motionfork/configs).
std::string ConfigDir(const std::string& flag_value);

// A one-line progress bar on stderr, redrawn at most ~10 times a second; on a non-terminal it
// prints a line every 10%. Finish() ends the line.
class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool enabled = true);
  ~ProgressBar();
  void Update(double fraction, const std::string& detail = "");
  void Finish();

 private:
  std::string label_;
  bool enabled_;
  bool tty_;
  bool finished_ = false;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

// A progress bar per stage of a library job (StageProgress): a new bar whenever the stage changes.
class StageBars {
 public:
  explicit StageBars(bool enabled) : enabled_(enabled) {}
  // The callback to hand the library; valid while this object lives.
  StageProgress Callback();
  void Finish() { bar_.reset(); }

 private:
  bool enabled_;
  std::string stage_;
  std::unique_ptr<ProgressBar> bar_;
};

// A training run's reports: a bar per epoch ("epoch 3/10"), made on the epoch's first step, and
// a line per finished epoch on stdout.
class EpochBars {
 public:
  EpochBars(int epochs, bool enabled) : epochs_(epochs), enabled_(enabled) {}
  void Update(int epoch, double fraction, const std::string& detail);
  // Ends the bar and prints "epoch 3/10 (12.3 s[, kl weight W]): name value ..." (values with
  // `digits` significant digits).
  void PrintEpoch(int epoch, double seconds,
                  const std::vector<std::pair<std::string, double>>& terms, int digits,
                  std::optional<double> kl_weight = std::nullopt);
  void Finish() { bar_.reset(); }

 private:
  int epochs_;
  bool enabled_;
  std::unique_ptr<ProgressBar> bar_;
};

// Prints a library's message as a line on stdout.
void PrintMessage(const std::string& message);

// A training run's callbacks (step(epoch, fraction, loss), epoch(log), message) reporting on bars.
template <typename Callbacks>
Callbacks LossEpochReports(EpochBars* bars) {
  Callbacks cb;
  cb.step = [bars](int epoch, double fraction, double loss) {
    bars->Update(epoch, fraction, "loss " + std::to_string(loss));
  };
  cb.epoch = [bars](const auto& log) {  // the KL weight where one anneals
    bars->PrintEpoch(log.epoch, log.seconds, log.terms, 5,
                     log.kl_weight > 0 ? std::optional<double>(log.kl_weight) : std::nullopt);
  };
  cb.message = PrintMessage;
  return cb;
}

// Prints a library's text report (core/text_format.h: WithThousands, Duration) as it is.
void PrintText(const std::string& text);
// "motionfork: warning: MESSAGE" on stderr (over any progress bar).
void PrintWarning(const std::string& message);

}  // namespace motionfork::app
