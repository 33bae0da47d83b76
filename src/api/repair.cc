// motionfork::Imputer and motionfork::Denoiser (include/motionfork/motionfork.h) over the HG-VAE
// and the Motion-DVAE: this file only adapts types.
#include <cmath>
#include <memory>
#include <stdexcept>

#include "bundle/dvae_bundle.h"
#include "bundle/hgvae_bundle.h"
#include "core/motion.h"
#include "denoise/dvae_model.h"
#include "imputation/hgvae_model.h"
#include "imputation/motion_imputation.h"
#include "motionfork/motionfork.h"
#include "positions.h"

namespace motionfork {

struct Imputer::Impl {
  HgvaeModel model;
  std::shared_ptr<const Skeleton> skeleton;
};

Imputer::Imputer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Imputer::~Imputer() = default;
Imputer::Imputer(Imputer&&) noexcept = default;
Imputer& Imputer::operator=(Imputer&&) noexcept = default;

Imputer Imputer::Load(const std::string& bundle_dir) {
  HgvaeModel model = LoadHgvaeModel(bundle_dir);
  auto skeleton = std::make_shared<const Skeleton>(model.skeleton());
  return Imputer(std::make_unique<Impl>(Impl{std::move(model), std::move(skeleton)}));
}

const std::vector<std::string>& Imputer::joint_names() const {
  return impl_->skeleton->joint_names();
}
double Imputer::fps() const { return impl_->model.manifest().fps; }
int Imputer::window_frames() const { return impl_->model.window(); }

Imputed Imputer::Impute(const std::vector<float>& positions) const {
  FramesOf(positions, impl_->skeleton->num_joints(), "Impute: positions");
  std::vector<float> filled = positions;
  std::vector<uint8_t> missing(positions.size(), 0);
  for (size_t i = 0; i < filled.size(); ++i) {
    if (std::isnan(filled[i])) {
      missing[i] = 1;
      filled[i] = 0.0f;
    }
  }
  const Motion motion(impl_->skeleton, fps(), std::move(filled));
  MotionImputation r = ImputeMotion(impl_->model, motion, missing, impl_->model.manifest().impute);
  return Imputed{r.motion.positions(), r.missing_values};
}

struct Denoiser::Impl {
  DvaeModel model;
  std::shared_ptr<const Skeleton> skeleton;
};

Denoiser::Denoiser(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Denoiser::~Denoiser() = default;
Denoiser::Denoiser(Denoiser&&) noexcept = default;
Denoiser& Denoiser::operator=(Denoiser&&) noexcept = default;

Denoiser Denoiser::Load(const std::string& bundle_dir) {
  DvaeModel model = LoadDvaeModel(bundle_dir);
  auto skeleton = std::make_shared<const Skeleton>(model.skeleton());
  return Denoiser(std::make_unique<Impl>(Impl{std::move(model), std::move(skeleton)}));
}

const std::vector<std::string>& Denoiser::joint_names() const {
  return impl_->skeleton->joint_names();
}
double Denoiser::fps() const { return impl_->model.manifest().fps; }

std::vector<float> Denoiser::Denoise(const std::vector<float>& positions) const {
  return Denoise(positions, "");
}

std::vector<float> Denoiser::Denoise(const std::vector<float>& positions,
                                     const std::string& mode) const {
  DenoiseOptions options = impl_->model.manifest().denoise;
  if (!mode.empty()) options.mode = ParseDenoiseMode(mode);
  if (FramesOf(positions, impl_->skeleton->num_joints(), "Denoise: positions") < 2) {
    throw std::invalid_argument("Denoise: expected at least 2 frames, got 1");
  }
  const Motion motion =
      MotionFromPositions(impl_->skeleton, fps(), positions, "Denoise: positions");
  return DenoiseMotion(impl_->model, motion, options).positions();
}

}  // namespace motionfork
