#include "generator/training/eval_experiment_text.h"

#include "core/text_format.h"

namespace motionfork {
namespace {

void AppendRow(std::string* s, const std::string& label, const Figures& f, bool fixed) {
  StringAppendf(s, "%-24s %8s %7.3f %7.3f %7.3f %7.3f %7.3f %9.1f", label.c_str(),
                WithThousands(f.windows).c_str(), f.apd, f.ade, f.fde, f.mmade, f.mmfde,
                f.mean_set_size);
  if (fixed) StringAppendf(s, " %10.3f %9.3f", f.apd_varied, f.apd_fixed);
  *s += "\n";
}

void AppendHeader(std::string* s, const EvalExperimentOptions& o, const EvalExperiment& x) {
  const ProtocolOptions& p = x.protocol;
  const EvalResult& r = x.result;
  if (!x.scorers_described.empty()) {
    StringAppendf(s, "plausibility figures: %s\n", x.scorers_described.c_str());
  }
  StringAppendf(s, "protocol:   %s (%s), %.6g Hz, t_his %d, t_pred %d\n", p.name.c_str(),
                p.path.c_str(), p.fps, p.t_his, p.t_pred);
  StringAppendf(s, "test:       %s: %s windows from %s clips (stride %d, %s)\n",
                x.test_source.c_str(), WithThousands(x.windows).c_str(),
                WithThousands(x.clips).c_str(), p.test_stride,
                p.test_include_last ? "last start included" : "last start excluded");
  StringAppendf(
      s, "multimodal: threshold %.6g m on the last history pose, mean set size %.1f, %s (%s)\n",
      p.multimodal_threshold, r.overall.mean_set_size,
      p.keep_singleton_sets
          ? "singleton sets kept"
          : ("singleton sets skipped: " + WithThousands(r.windows_skipped) + " windows").c_str(),
      x.multimodal_cached ? "from the cache" : "computed");
  StringAppendf(s, "predictor:  %s%s%s\n", x.predictor_name.c_str(),
                x.predictor_description.empty() ? "" : ": ", x.predictor_description.c_str());
  StringAppendf(s, "samples:    K = %d, seed %llu%s\n", o.k,
                static_cast<unsigned long long>(o.seed),
                r.fixed_part.empty()
                    ? ""
                    : (", fixed part '" + r.fixed_part + "' (shared by every sample)").c_str());
  if (x.overlaps_training) {
    StringAppendf(
        s, "note:       the evaluated windows overlap the nearest-neighbour training windows\n");
  }
}

void AppendTable(std::string* s, const EvalExperiment& x) {
  const EvalResult& r = x.result;
  const bool fixed = !r.fixed_part.empty();
  StringAppendf(s, "\n%-24s %8s %7s %7s %7s %7s %7s %9s", "action", "windows", "APD", "ADE", "FDE",
                "MMADE", "MMFDE", "mm set");
  if (fixed) StringAppendf(s, " %10s %9s", "APD varied", "APD fixed");
  *s += "\n";
  AppendRow(s, "all", r.overall, fixed);
  if (x.actions.size() > 1 || (x.actions.size() == 1 && !x.actions[0].empty())) {
    for (size_t a = 0; a < x.actions.size(); ++a) {
      if (r.per_action[a].windows == 0) continue;
      AppendRow(s, x.actions[a].empty() ? "(unlabelled)" : x.actions[a], r.per_action[a], fixed);
    }
  }
  StringAppendf(
      s, "\nmetres; APD, ADE, FDE: whole pose vectors (%d numbers a frame), min over samples\n",
      x.pose_dims);
}

void AppendTime(std::string* s, const EvalExperiment& x) {
  const EvalResult& r = x.result;
  const double measured = r.seconds_predicting + r.seconds_metrics + r.seconds_scoring;
  StringAppendf(
      s,
      "time:       %s in all: loading %s, test windows + multimodal sets %s, predictor setup "
      "%s;\n            summed over the threads that measured windows: predictor %s (%.0f%%), "
      "metrics %s (%.0f%%)\n",
      Duration(x.seconds_total).c_str(), Duration(x.seconds_loading).c_str(),
      Duration(x.seconds_multimodal).c_str(), Duration(x.seconds_predictor_setup).c_str(),
      Duration(r.seconds_predicting).c_str(),
      measured > 0 ? 100 * r.seconds_predicting / measured : 0.0,
      Duration(r.seconds_metrics).c_str(), measured > 0 ? 100 * r.seconds_metrics / measured : 0.0);
}

// Where the body goes: the futures' world root and feet, beside the root-relative table.
void AppendRootTable(std::string* s, const EvalExperiment& x) {
  if (!x.root_figures) return;
  const EvalResult& r = x.result;
  const bool feet = !x.feet.empty();
  StringAppendf(s, "where the body goes (world root, up %s%s):\n%-24s %8s %8s %8s",
                x.protocol.up.c_str(),
                feet ? (("; foot skating of " + x.feet + ", m a frame").c_str()) : "", "action",
                "root ADE", "root FDE", "spread");
  if (feet) StringAppendf(s, " %8s %8s", "skating", "truth");
  *s += "\n";
  auto row = [&](const std::string& label, const Figures& f) {
    StringAppendf(s, "%-24s %8.3f %8.3f %8.3f", label.c_str(), f.root.ade, f.root.fde,
                  f.root.final_spread);
    if (feet) StringAppendf(s, " %8.4f %8.4f", f.root.skating, f.root.truth_skating);
    *s += "\n";
  };
  row("all", r.overall);
  if (x.actions.size() > 1) {
    for (size_t a = 0; a < x.actions.size(); ++a) {
      if (r.per_action[a].windows > 0) row(x.actions[a], r.per_action[a]);
    }
  }
  StringAppendf(s,
                "metres; root ADE, FDE: the root's 3D distance, min over samples; spread: mean "
                "distance between the samples' last roots on the ground\n");
}

}  // namespace

// The protocol's published figures beside this run's, and where this run leads each.
void AppendPublished(std::string* s, const EvalExperimentOptions& o, const EvalExperiment& x) {
  const std::vector<PublishedFigures>& published = x.protocol.published;
  if (published.empty()) return;
  const Figures& f = x.result.overall;
  std::vector<std::string> differences = DifferencesFromPublished(o, x);
  std::string note = "K = 50 on the whole test split, as published";
  if (!differences.empty()) {
    note = "NOT comparable: this run has ";
    for (size_t i = 0; i < differences.size(); ++i) note += (i ? ", " : "") + differences[i];
  }
  StringAppendf(s, "\npublished figures (%s; %s):\n%-16s %7s %7s %7s %7s %7s  %s\n",
                x.protocol.path.c_str(), note.c_str(), "method", "APD", "ADE", "FDE", "MMADE",
                "MMFDE", "this run leads on");
  StringAppendf(s, "%-16s %7.3f %7.3f %7.3f %7.3f %7.3f\n", x.predictor_name.c_str(), f.apd, f.ade,
                f.fde, f.mmade, f.mmfde);
  for (const PublishedFigures& p : published) {
    const std::vector<std::string> leads = FiguresLeading(f, p);
    std::string lead = leads.empty() ? "none" : "";
    for (size_t i = 0; i < leads.size(); ++i) lead += (i ? ", " : "") + leads[i];
    StringAppendf(s, "%-16s %7.3f %7.3f %7.3f %7.3f %7.3f  %s (%zu of 5)   [%s]\n",
                  p.method.c_str(), p.apd, p.ade, p.fde, p.mmade, p.mmfde, lead.c_str(),
                  leads.size(), p.source.c_str());
  }
}

std::string EvalExperimentText(const EvalExperimentOptions& options, const EvalExperiment& x) {
  std::string s;
  AppendHeader(&s, options, x);
  AppendTable(&s, x);
  AppendRootTable(&s, x);
  AppendTime(&s, x);
  AppendPublished(&s, options, x);
  return s;
}

}  // namespace motionfork
