// The protocol's metrics (../shared/specs/protocols.md; DLow's evaluation code, GSPS's tables).
//
// A future is [T, D]: T = t_pred frames of pose vectors (root-relative joints without the root,
// D = 3 (J - 1) numbers), metres. K samples of one history are [K, T, D], contiguous. Distances are
// L2 norms of whole pose vectors (not per-joint MPJPE).
#pragma once

#include <vector>

namespace motionfork {

// APD (diversity): mean over ordered pairs i != j of ||x_i - x_j||, x a whole flattened future
// [T * D] (equal to the mean over unordered pairs, as scipy's pdist in DLow's code).
// Throws std::invalid_argument for K < 2 (APD needs a pair).
double Apd(const float* samples, int K, int T, int D);

// APD over some pose-vector components only (e.g. one body part's joints, 3 per joint): dims are
// indices into [0, D). Used for the controllable setting. Throws for K < 2 or a dim out of range.
double ApdOfDims(const float* samples, int K, int T, int D, const std::vector<int>& dims);

struct Displacement {
  double ade = 0;  // metres
  double fde = 0;  // metres
};

// Against one ground-truth future [T, D]: ADE = min over samples of the mean over frames of
// ||s_t - g_t||; FDE = min over samples of ||s_{T-1} - g_{T-1}||. The two minima are taken
// separately (they may pick different samples), as in DLow's code. Throws for K < 1.
Displacement MinDisplacement(const float* samples, int K, int T, int D, const float* truth);

// The forecasting score of many histories: the mean over histories h of MinDisplacement of
// predictions [H, K, T, D] (history h's K samples) to futures [H, T, D]. Throws
// std::invalid_argument when the sizes do not match H, K, T, D.
Displacement MeanMinDisplacement(const std::vector<float>& predictions,
                                 const std::vector<float>& futures, int H, int K, int T, int D);

// The same figures for many ground truths at once (MMADE / MMFDE need one per member of a
// multimodal set) through per-frame matrix products in single precision, on poses centred on the
// first sample (distances within 1 cm recomputed directly). Agrees with MinDisplacement to ~1e-6 m.
// Scratch memory is kept across calls (no allocation once warm): one object per thread.
class DisplacementWorkspace {
 public:
  // truths: M pointers to [T, D] futures. out: resized to M; out[m] is the MinDisplacement of
  // the samples to truths[m].
  void Run(const float* samples, int K, int T, int D, const std::vector<const float*>& truths,
           std::vector<Displacement>* out);

 private:
  std::vector<float> samples_;    // [T, K, D] centred
  std::vector<float> sample_sq_;  // [T, K]
  std::vector<float> truths_;     // [T, M, D] centred
  std::vector<float> truth_sq_;   // [T, M]
  std::vector<float> cross_;      // [K, M] products, then distances of the current frame
  std::vector<float> sum_;        // [K, M] sum over frames of distances
};

// Per-window figures. MMADE / MMFDE: the mean over the window's multimodal set of the
// MinDisplacement to each member's future.
struct WindowMetrics {
  double apd = 0;
  double ade = 0;
  double fde = 0;
  double mmade = 0;
  double mmfde = 0;
};

// Several windows' metrics summed (each figure on its own), and the sum over n windows as means.
WindowMetrics& operator+=(WindowMetrics& sum, const WindowMetrics& m);
WindowMetrics operator/(WindowMetrics sum, double n);

}  // namespace motionfork
