#include "pipeline/constraint_fit.h"

#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "config/config_paths.h"
#include "config/constraint_config.h"
#include "config/protocol_config.h"
#include "config/protocol_dataset.h"
#include "config/skeleton_config.h"
#include "constraints/checker.h"
#include "dataset/dataset.h"

namespace motionfork::pipeline {
namespace {

std::string Fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

std::string Thousands(long long n) {
  std::string digits = std::to_string(n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

// Words of text re-flowed into lines of at most `width` characters.
std::string Wrap(const std::string& text, size_t width = 96) {
  std::string out, line, word;
  auto flush_word = [&] {
    if (word.empty()) return;
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      out += line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    word.clear();
  };
  for (char c : text) {
    if (c == ' ') {
      flush_word();
    } else {
      word += c;
    }
  }
  flush_word();
  return out + line + "\n";
}

// Frames of `clips` against `set`: how many break some range (or have an undefined angle).
FrameCheck CheckClips(const ConstraintSet& set, const Dataset& ds, const std::vector<int>& clips,
                      const DegeneracyOptions& degeneracy) {
  FrameCheck f;
  f.violations.assign(set.num_constraints(), 0);
  for (int i : clips) {
    const CheckResult r = Check(set, ds.clips[i].motion, degeneracy);
    f.frames += r.num_frames;
    for (int t = 0; t < r.num_frames; ++t) {
      bool bad = false;
      for (int c = 0; c < r.num_constraints; ++c) {
        const AngleStatus s = r.at(t, c);
        if (IsViolation(s)) ++f.violations[c];
        bad |= s != AngleStatus::kInside;
      }
      f.flagged += bad;
    }
  }
  return f;
}

// Each training subject fitted out: ranges from the others' angles, checked on its frames.
std::vector<LeftOutSubject> LeaveOneOut(const ConstraintSetSpec& definitions,
                                        const ConstraintSet& set, const Skeleton& skeleton,
                                        const Dataset& ds, const std::vector<int>& train,
                                        const FitOptions& fit, const StageProgress& progress) {
  std::map<std::string, std::vector<int>> by_subject;
  for (int i : train) by_subject[ds.clips[i].subject].push_back(i);
  if (by_subject.size() < 2) {
    throw std::invalid_argument(
        "leave-one-out needs training clips of at least two subjects (Bandai: styles); found " +
        std::to_string(by_subject.size()) +
        (by_subject.size() == 1 ? " ('" + by_subject.begin()->first + "')" : std::string()));
  }
  std::vector<RangeFitter> fitters;
  for (const auto& [subject, clips] : by_subject) {
    fitters.emplace_back(set, fit);
    for (int i : clips) fitters.back().Add(ds.clips[i].motion);
  }
  std::vector<LeftOutSubject> out;
  size_t g = 0;
  for (const auto& [subject, clips] : by_subject) {
    RangeFitter others(set, fit);
    for (size_t h = 0; h < fitters.size(); ++h)
      if (h != g) others.Merge(fitters[h]);
    LeftOutSubject l;
    l.subject = subject;
    l.clips = static_cast<long long>(clips.size());
    l.ranges = others.Fit();
    const ConstraintSet fitted =
        ConstraintSet::Build(WithFittedRanges(definitions, l.ranges), skeleton);
    l.check = CheckClips(fitted, ds, clips, fit.degeneracy);
    out.push_back(std::move(l));
    ++g;
    ReportProgress(progress, "leaving one subject out", double(g) / by_subject.size(), subject);
  }
  return out;
}

bool HasAnatomicalLimits(const ConstraintSetSpec& spec) {
  for (const ConstraintSpec& c : spec.constraints)
    if (c.has_anatomical) return true;
  return false;
}

std::string Header(const ConstraintFitRequest& o, const ConstraintFit& f,
                   const std::string& skeleton_name, size_t train_clips, size_t test_clips) {
  const std::string& skeleton = f.protocol.skeleton;
  const FitOptions& fit = o.fit;
  // Shipped names are shown as the file in the source tree, paths as given.
  const std::string shown =
      std::filesystem::is_regular_file(o.constraints.empty() ? std::string() : o.constraints)
          ? o.constraints
          : "configs/constraints/" + (o.constraints.empty() ? skeleton : o.constraints) + ".yaml";
  std::string about =
      "Definitions: " + shown +
      " (re-running the command refits its ranges). Fitted on protocol '" + f.protocol.name +
      "', train split: " + Thousands(train_clips) + " clips, " + Thousands(f.train_frames) +
      " frames. Each range: percentiles " + Fmt("%g", fit.low_percentile) + " / " +
      Fmt("%g", fit.high_percentile) +
      " of the angle over those frames (left and right pooled), widened by " +
      Fmt("%g", fit.margin_deg) + " degrees" +
      (HasAnatomicalLimits(f.definitions) ? ", then to its 'anatomical' limit where it has one"
                                          : "") +
      (fit.round_deg > 0 ? ", rounded outwards to " + Fmt("%g", fit.round_deg) + " degrees" : "") +
      ".";
  if (f.test.frames > 0) {
    about += " Held-out test split: " + Thousands(test_clips) + " clips, " +
             Thousands(f.test.frames) + " frames, " +
             Fmt("%.3f", 100.0 * f.test.flagged / f.test.frames) + "% of them outside some range.";
  }
  double worst = 0;
  if (const LeftOutSubject* most = MostFlaggedLeftOut(f, &worst)) {
    const std::string& who = most->subject;
    about += " Each of the " + std::to_string(f.left_out.size()) +
             " training subjects left out in turn (ranges fitted on the others): at most " +
             Fmt("%.3f", worst) + "% of its frames outside some range ('" + who + "').";
  }
  return "Angle-range constraints for the " + skeleton_name +
         " skeleton. Ranges FITTED from data by:\n  " + o.command_line + "\n" + Wrap(about) +
         "Format: configs/constraints/README.md.";
}

}  // namespace

const LeftOutSubject* MostFlaggedLeftOut(const ConstraintFit& fit, double* percent) {
  const LeftOutSubject* most = nullptr;
  *percent = 0;
  for (const LeftOutSubject& l : fit.left_out) {
    const double share = l.check.frames ? 100.0 * l.check.flagged / l.check.frames : 0.0;
    if (share >= *percent) *percent = share, most = &l;
  }
  return most;
}

ConstraintFit FitConstraints(const ConstraintFitRequest& o) {
  Validate(o.fit);
  ConstraintFit f;
  f.protocol = LoadProtocolConfig(ResolveConfigPath(o.config_dir, "protocols", o.protocol));
  const SkeletonConfig skeleton =
      LoadSkeletonConfig(ResolveConfigPath(o.config_dir, "skeletons", f.protocol.skeleton));
  const std::string definitions = ResolveConfigPath(
      o.config_dir, "constraints", o.constraints.empty() ? f.protocol.skeleton : o.constraints);
  ConstraintLoadOptions load_options;
  load_options.require_ranges = false;
  f.definitions = LoadConstraintConfig(definitions, load_options);
  ConstraintBuildOptions build_options;
  build_options.require_ranges = false;
  // Bind before the (long) dataset load, so a bad definition fails at once.
  const ConstraintSet set = ConstraintSet::Build(f.definitions, *skeleton.skeleton, build_options);

  const Dataset ds = LoadDataset(
      f.protocol, skeleton, o.data,
      ReportingLoadOptions(o.cache_dir, o.split_file, o.progress, "loading " + f.protocol.name));
  const std::vector<int> train = ds.ClipIndices(Split::kTrain), test = ds.ClipIndices(Split::kTest);
  if (train.empty()) {
    throw std::invalid_argument("no training clips in " + o.data + " under protocol '" +
                                f.protocol.name + "': nothing to fit");
  }
  RangeFitter fitter(set, o.fit);
  for (size_t i = 0; i < train.size(); ++i) {
    fitter.Add(ds.clips[train[i]].motion);
    ReportProgress(o.progress, "measuring angles", double(i + 1) / train.size(),
                   ds.clips[train[i]].name);
  }
  f.ranges = fitter.Fit();
  f.train_frames = fitter.frames();
  const ConstraintSetSpec fitted = WithFittedRanges(f.definitions, f.ranges);
  f.fitted = ConstraintSet::Build(fitted, *skeleton.skeleton);
  f.test = CheckClips(*f.fitted, ds, test, o.fit.degeneracy);
  if (o.leave_one_out) {
    f.left_out = LeaveOneOut(f.definitions, set, *skeleton.skeleton, ds, train, o.fit, o.progress);
  }
  f.yaml = FormatConstraintConfig(
      fitted, Header(o, f, skeleton.skeleton->name(), train.size(), test.size()));
  return f;
}

}  // namespace motionfork::pipeline
