#include "denoise/training/dvae_evaluation.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "core/motion_noise.h"
#include "core/resample.h"
#include "denoise/denoise_metrics.h"
#include "denoise/filter_tuning.h"

namespace motionfork {
namespace {

using Sequences = std::vector<std::vector<float>>;

// Up to `count` training clips, spread evenly (positions). Throws when the split has none.
Sequences TuningClips(const Dataset& ds, int count) {
  const std::vector<int> train = ds.ClipIndices(Split::kTrain);
  if (train.empty()) {
    throw std::invalid_argument(
        "dvae eval: the filters are tuned on training clips, and the protocol's training split "
        "is empty");
  }
  const int used = std::clamp<int>(count, 1, static_cast<int>(train.size()));
  Sequences out;
  for (int i = 0; i < used; ++i)
    out.push_back(ds.clips[train[static_cast<size_t>(i) * train.size() / used]].motion.positions());
  return out;
}

Sequences SlowedDown(Sequences clips, int J, double factor) {
  if (factor != 1)
    for (auto& q : clips) q = SlowDown(q, J, factor);
  return clips;
}

struct Figures {
  double err = 0, accel = 0;
};

Figures Measure(const Sequences& out, const Sequences& clean, int J, double fps) {
  Figures f;
  double frames = 0;
  for (size_t c = 0; c < out.size(); ++c) {
    const double n = static_cast<double>(out[c].size() / (3 * J));
    f.err += MeanJointError(out[c], clean[c]) * n;
    f.accel += MeanAcceleration(out[c], J, fps) * n;
    frames += n;
  }
  f.err /= frames;
  f.accel /= frames;
  return f;
}

Sequences Noisy(const Sequences& clean, const std::string& noise, uint64_t seed, int J) {
  const NoiseSpec spec = ParseNoiseSpec(noise);
  Sequences noisy = clean;
  std::mt19937_64 rng(seed);
  for (auto& q : noisy) AddNoise(spec, q.data(), static_cast<int>(q.size() / (3 * J)), J, rng);
  return noisy;
}

// Each history is denoised with the window() frames that end with it (no future frame is seen).
ForecastingFigures Forecasting(const DvaeModel& model, const Dataset& ds,
                               const std::vector<int>& test, const DvaeEvalOptions& o,
                               const DenoiseOptions& reg) {
  const HistoryForecaster& fc = o.forecaster;
  if (fc.t_his != ds.protocol.t_his || fc.joints != model.skeleton().joint_names()) {
    throw std::invalid_argument(fc.name + ": the forecaster's history (" +
                                std::to_string(fc.t_his) +
                                " frames) or skeleton does not match the protocol '" +
                                ds.protocol.name + "' of the Motion-DVAE");
  }
  std::vector<const Clip*> test_clips;
  for (int c : test) test_clips.push_back(&ds.clips[c]);
  const TestSet ts = BuildTestSet(test_clips, ds.protocol);
  const HistoryForecastProbe probe(ts, o.forecast_windows, o.k, fc);
  const int T = ts.t_his, J = model.joints(), W = model.window();
  Sequences contexts;
  for (int w : probe.windows()) {
    const std::vector<float>& p = test_clips[ts.windows[w].clip]->motion.positions();
    const int end = ts.windows[w].start + T;
    contexts.emplace_back(p.begin() + static_cast<size_t>(std::max(0, end - W)) * J * 3,
                          p.begin() + static_cast<size_t>(end) * J * 3);
  }
  auto histories = [&](const Sequences& sequences) {
    std::vector<float> h;
    for (const auto& q : sequences) {
      const int n = static_cast<int>(q.size() / (3 * J));
      AppendPoseVectors(q.data() + static_cast<size_t>(n - T) * J * 3, T, J, &h);
    }
    return h;
  };
  ForecastingFigures f{fc.name, o.k, probe.count(), probe.Score(histories(contexts)), {}};
  for (size_t n = 0; n < o.noises.size(); ++n) {
    const Sequences noisy = Noisy(contexts, o.noises[n], o.seed + 7777 + n, J);
    f.settings.push_back({o.noises[n],
                          probe.Score(histories(noisy)),
                          probe.Score(histories(model.Denoise(noisy, reg))),
                          {}});
  }
  return f;
}

}  // namespace

const FilterFigure* DenoisingRow::best_filter() const {
  const FilterFigure* best = nullptr;
  for (const FilterFigure& f : filters) {
    if (!best || f.cm < best->cm) best = &f;
  }
  return best;
}

DvaeEvaluation EvaluateDvae(const DvaeModel& model, const Dataset& ds, const DvaeEvalOptions& o,
                            const std::function<void(const DvaeEvaluation&)>& report) {
  const int J = model.joints();
  const double fps = model.manifest().fps;
  const std::vector<int> test = ds.ClipIndices(Split::kTest);
  if (test.empty()) throw std::invalid_argument("the protocol's test split is empty");
  DvaeEvaluation e;
  const int used = std::min<int>(o.clips, static_cast<int>(test.size()));
  Sequences clean;
  for (int i = 0; i < used; ++i) {
    clean.push_back(ds.clips[test[static_cast<size_t>(i) * test.size() / used]].motion.positions());
  }
  const Sequences tuning = SlowedDown(TuningClips(ds, o.tuning_clips), J, o.slow);
  clean = SlowedDown(clean, J, o.slow);
  e.slow = o.slow;
  e.clips = used;
  e.optimisation_clips = std::min(o.optimisation_clips, used);
  for (int c = 0; c < used; ++c) {
    const long long n = static_cast<long long>(clean[c].size() / (3 * J));
    e.frames += n;
    if (c < e.optimisation_clips) e.optimisation_frames += n;
  }
  e.test_style = ds.clips[test[0]].subject;
  e.tuning_clips = static_cast<int>(tuning.size());
  for (const auto& q : tuning) e.tuning_frames += static_cast<long long>(q.size() / (3 * J));
  e.clean_accel = Measure(clean, clean, J, fps).accel;
  DenoiseOptions reg = o.denoise;
  reg.mode = DenoiseMode::kRegression;
  DenoiseOptions opt = reg;
  opt.mode = DenoiseMode::kOptimisation;
  DenoiseOptions refined = reg;
  refined.mode = DenoiseMode::kRefiner;
  e.refiner = model.manifest().refiner.enabled();
  e.samples = reg.samples;
  e.iterations = opt.iterations;
  if (report) report(e);
  double reg_seconds = 0, opt_seconds = 0, refine_seconds = 0;
  const Sequences opt_clean(clean.begin(), clean.begin() + e.optimisation_clips);
  for (size_t n = 0; n < o.noises.size(); ++n) {
    const Sequences noisy = Noisy(clean, o.noises[n], o.seed + 1000 * n, J);
    DenoiseStats st, st_opt;
    const Sequences denoised = model.Denoise(noisy, reg, &st);
    reg_seconds += st.seconds;
    const Figures fn = Measure(noisy, clean, J, fps), fd = Measure(denoised, clean, J, fps);
    Figures fo{NAN, NAN}, fon{NAN, NAN};
    if (e.optimisation_clips > 0) {
      const Sequences opt_in(noisy.begin(), noisy.begin() + e.optimisation_clips);
      fo = Measure(model.Denoise(opt_in, opt, &st_opt), opt_clean, J, fps);
      fon = Measure(opt_in, opt_clean, J, fps);
      opt_seconds += st_opt.seconds;
    }
    const double c = e.clean_accel;
    DenoisingRow row;
    row.noise = o.noises[n];
    row.noisy_cm = 100 * fn.err;
    row.denoised_cm = 100 * fd.err;
    row.removed = 1 - fd.err / fn.err;
    row.optimised_cm = 100 * fo.err;
    row.optimised_noisy_cm = 100 * fon.err;
    row.removed_optimised = 1 - fo.err / fon.err;
    row.accel_ratio_noisy = fn.accel / c;
    row.accel_ratio_denoised = fd.accel / c;
    row.accel_ratio_optimised = fo.accel / c;
    if (e.refiner) {
      DenoiseStats st_ref;
      const Figures fr = Measure(model.Denoise(noisy, refined, &st_ref), clean, J, fps);
      refine_seconds += st_ref.seconds;
      row.refined_cm = 100 * fr.err;
      row.removed_refined = 1 - fr.err / fn.err;
      row.accel_ratio_refined = fr.accel / c;
    }
    // Each filter tuned on the training clips under this noise kind (other draws), then applied
    // to the test clips' noisy motion.
    const Sequences tuning_noisy = Noisy(tuning, o.noises[n], o.seed + 500000 + 1000 * n, J);
    for (FilterKind kind : {FilterKind::kGaussian, FilterKind::kSavitzkyGolay, FilterKind::kOneEuro,
                            FilterKind::kHampel}) {
      const TunedFilter tuned = TuneFilter(kind, tuning_noisy, tuning, J, fps, o.threads);
      Sequences filtered;
      for (const auto& q : noisy) filtered.push_back(ApplyFilter(tuned.setting, q, J, fps));
      const Figures ff = Measure(filtered, clean, J, fps);
      row.filters.push_back({FilterName(kind), DescribeFilter(tuned.setting), 100 * tuned.error_m,
                             100 * ff.err, 1 - ff.err / fn.err, ff.accel / c});
    }
    e.settings.push_back(std::move(row));
    if (report) report(e);
  }
  e.regression_frames_per_s = e.frames * o.noises.size() / reg_seconds;
  e.optimisation_frames_per_s = e.optimisation_frames * o.noises.size() / opt_seconds;
  if (e.refiner) e.refiner_frames_per_s = e.frames * o.noises.size() / refine_seconds;
  if (o.forecaster.forecast)
    e.forecasting = Forecasting(model, ds, test, o, e.refiner ? refined : reg);
  return e;
}

}  // namespace motionfork
