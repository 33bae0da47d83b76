// Samples of an HG-VAE's prior as a motion (`motionfork hgvae sample`).
#pragma once

#include <cstdint>

#include "core/motion.h"
#include "imputation/hgvae_model.h"

namespace motionfork {

// `count` windows (HgvaeModel::Sample) one after another on the model's skeleton and frame rate,
// root at the origin (windows are root-relative). class_index -1 = unconditional; sampled false =
// each level's prior mean.
Motion SampleMotion(const HgvaeModel& model, int count, int class_index, uint64_t seed,
                    bool sampled);

}  // namespace motionfork
