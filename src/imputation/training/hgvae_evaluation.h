// The `motionfork hgvae eval` experiment: an HG-VAE's figures on its protocol's test split —
// likelihood (ELBO, KL per level), imputation against mean imputation, out-of-distribution AUROC
// and, given a forecaster, the forecasting ADE/FDE from clean, mean-imputed, HG-VAE-imputed and
// interpolated / rigid-limb / refiner-filled histories.
// Part of the imputation training target: it reads datasets.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/progress.h"
#include "dataset/dataset.h"
#include "eval/history_forecasting.h"
#include "imputation/gap_imputation.h"
#include "imputation/hgvae_experiments.h"
#include "imputation/hgvae_model.h"

namespace motionfork {

struct HgvaeEvalOptions {
  int windows = 1000;  // test windows, spread evenly
  int gap_clips = 40;  // whole test clips of the gap experiment (gap_imputation.h), spread evenly;
                       // 0: no such experiment
  uint64_t seed = 0;   // masks and samples
  bool likelihood_only = false;
  ImputeOptions impute;          // imputation settings (usually the bundle's)
  HistoryForecaster forecaster;  // forecast empty = no forecasting figures
  int forecast_windows = 500;    // protocol test windows forecast
  int k = 50;                    // futures per history
  // The forecasting rows to run, by occlusion name ("random 50%", "left arm"; StandardOcclusions);
  // empty: all. Each keeps the masks it has in a run of all.
  std::vector<std::string> forecast_occlusions;
  // Test clips played this many times slower first (core/resample.h SlowDown; 1: as they are):
  // every figure, the forecasting ones too, on slower motion than the models were trained on.
  double slow = 1;
  StageProgress progress;  // "imputation", "gaps", "forecasting"
};

// Means over windows (nats per window, densities in metres; squared errors in m^2 per value).
struct HgvaeLikelihood {
  double elbo_nats = 0, recon_mse_m2 = 0, recon_mse_sampled_m2 = 0;
  std::vector<double> kl_levels;
  double kl_total = 0, posterior_score_mean = 0, joint_score_mean = 0;
};

// Clean windows against degraded ones: AUROC of the joint and the posterior score, and the share
// of degraded windows the bundle's rule flags.
struct OodTest {
  std::string degradation;
  double auroc_joint = 0, auroc_posterior = 0, flagged = 0;
};

struct HgvaeEvaluation {
  int windows = 0;  // test windows used
  int window_frames = 0;
  int stochastic_levels = 0;
  double slow = 1;  // HgvaeEvalOptions::slow
  HgvaeLikelihood likelihood;
  bool likelihood_only = false;  // the rest is empty
  std::vector<ImputationFigure> imputation;
  int gap_clips = 0;            // whole test clips of the gap experiment
  std::vector<GapFigure> gaps;  // the HG-VAE beside the classical fills, over whole clips
  double clean_flagged = 0;     // share of clean windows flagged
  std::vector<OodTest> ood;
  std::optional<ForecastingFigures> forecasting;  // before: mean-imputed, after: HG-VAE-imputed,
                                                  // others: linear, spline, rigid limb, refiner
};

// Test-split windows of the model's length: every window-th start of every test clip, at most
// `limit` spread evenly. [count, T, N]. Throws when no test clip is long enough.
std::vector<float> HgvaeTestWindows(const Dataset& dataset, int window, int limit);

HgvaeEvaluation EvaluateHgvae(const HgvaeModel& model, const Dataset& dataset,
                              const HgvaeEvalOptions& options);

}  // namespace motionfork
