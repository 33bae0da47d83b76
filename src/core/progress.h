// How long-running library jobs report progress: a stage label ("loading bandai", "evaluating
// zero-velocity"), the share of that stage done (0..1) and a detail (e.g. the current file). The
// caller draws it (apps: a progress bar per stage); libraries never print.
#pragma once

#include <functional>
#include <string>

namespace motionfork {

using StageProgress =
    std::function<void(const std::string& stage, double fraction, const std::string& detail)>;

// Calls `progress` when it is set.
inline void ReportProgress(const StageProgress& progress, const std::string& stage, double fraction,
                           const std::string& detail = "") {
  if (progress) progress(stage, fraction, detail);
}

// A warning for the caller to show, not a stage: a job that carries on after a problem (e.g. an
// unwritable cache) reports stage kWarningStage with the message as the detail.
inline constexpr char kWarningStage[] = "warning";
inline void ReportWarning(const StageProgress& progress, const std::string& message) {
  if (progress) progress(kWarningStage, 0, message);
}

}  // namespace motionfork
