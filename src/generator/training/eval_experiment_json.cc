#include "generator/training/eval_experiment_json.h"

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/json_members.h"

namespace motionfork {
namespace {

using json = nlohmann::ordered_json;

// The figures of one group, with its window count.
json FiguresJson(const Figures& f, bool fixed, const std::vector<std::string>& scorers,
                 const EvalExperiment& x) {
  json j;
  MOTIONFORK_JSON_MEMBERS(j, f, windows, apd, ade, fde, mmade, mmfde);
  j["mean_multimodal_set_size"] = f.mean_set_size;
  if (fixed) j.update({{"apd_varied", f.apd_varied}, {"apd_fixed", f.apd_fixed}});
  for (size_t s = 0; s < scorers.size() && s < f.predicted_scores.size(); ++s) {
    j[scorers[s]] = f.predicted_scores[s];
    j[scorers[s] + "_gt"] = f.truth_scores[s];
  }
  if (x.root_figures) {
    json root = {{"ade", f.root.ade}, {"fde", f.root.fde}, {"final_spread", f.root.final_spread}};
    if (!x.feet.empty()) {
      root.update({{"foot_skating", f.root.skating}, {"foot_skating_gt", f.root.truth_skating}});
    }
    j["root"] = root;
  }
  return j;
}

json PredictorJson(const EvalExperiment& x) {
  json predictor = {{"name", x.predictor_name},
                    {"kind", x.learned ? "model" : "baseline"},
                    {"description", x.predictor_description},
                    {"bundle_hash", x.bundle_hash.empty() ? json() : json(x.bundle_hash)}};
  if (x.training_windows >= 0) predictor["training_windows"] = x.training_windows;
  return predictor;
}

}  // namespace

json EvalExperimentJson(const EvalExperimentOptions& o, const EvalExperiment& x) {
  const ProtocolOptions& p = x.protocol;
  const EvalResult& r = x.result;
  const bool fixed = !r.fixed_part.empty();
  const bool from_clips = !o.clips.empty();
  json j = {
      {"protocol", p.name},
      {"protocol_path", p.path},
      {"fps", p.fps},
      {"t_his", p.t_his},
      {"t_pred", p.t_pred},
      {"test_stride", p.test_stride},
      {"test_include_last", p.test_include_last},
      {"split", from_clips ? json() : json(o.subset)},
      {"clips_dir", from_clips ? json(o.clips) : json()},
      {"turn_degrees", o.turn_degrees},
      {"clips", x.clips},
      {"windows", x.windows},
      {"windows_evaluated", r.overall.windows},
      {"windows_skipped_singleton", r.windows_skipped},
      {"multimodal_threshold", p.multimodal_threshold},
      {"keep_singleton_sets", p.keep_singleton_sets},
      {"k", o.k},
      {"seed", o.seed},
      {"predictor", PredictorJson(x)},
      {"fixed_part", fixed ? json(r.fixed_part) : json()},
      {"root_figures", x.root_figures ? json({{"up", p.up},
                                              {"feet", x.feet.empty() ? json() : json(x.feet)},
                                              {"contact_height_m", RootOptions().contact_height}})
                                      : json()}};
  json overall = FiguresJson(r.overall, fixed, x.scorer_names, x);
  overall.erase("windows");  // the top level's "windows" counts every test window
  j.update(overall);
  json per_action = json::object();
  for (size_t a = 0; a < x.actions.size(); ++a) {
    if (r.per_action[a].windows > 0) {
      per_action[x.actions[a]] = FiguresJson(r.per_action[a], fixed, x.scorer_names, x);
    }
  }
  j["per_action"] = per_action;
  json published = json::array();
  for (const PublishedFigures& pf : p.published) {
    published.push_back({{"method", pf.method},
                         {"source", pf.source},
                         {"apd", pf.apd},
                         {"ade", pf.ade},
                         {"fde", pf.fde},
                         {"mmade", pf.mmade},
                         {"mmfde", pf.mmfde},
                         {"this_run_leads_on", FiguresLeading(r.overall, pf)}});
  }
  j["published"] = published;
  j["published_not_comparable_because"] = DifferencesFromPublished(o, x);
  j["seconds"] = {{"total", x.seconds_total},
                  {"loading", x.seconds_loading},
                  {"test_windows_and_multimodal", x.seconds_multimodal},
                  {"predictor_setup", x.seconds_predictor_setup},
                  {"predictor", r.seconds_predicting},
                  {"metrics", r.seconds_metrics},
                  {"scorers", r.seconds_scoring}};
  return j;
}

}  // namespace motionfork
