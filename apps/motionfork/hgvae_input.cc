#include "hgvae_input.h"

#include <cmath>
#include <cstdio>

#include "config/skeleton_config.h"
#include "core/error.h"
#include "core/resample.h"
#include "imputation/occlusion.h"

namespace motionfork::app {

MotionWithGaps LoadMotionWithGaps(const std::string& path, const MotionInputOptions& input,
                                  const std::string& config_dir,
                                  const std::shared_ptr<const Skeleton>& skeleton, double fps,
                                  const std::vector<std::string>& mask_specs, uint64_t seed) {
  std::vector<uint8_t> missing;
  LoadedMotion lm = LoadMotionInput(path, input, config_dir, &missing);
  SkeletonConfig onto;
  onto.skeleton = skeleton;
  onto.source = lm.skeleton_config ? lm.skeleton_config->source : skeleton;
  if (lm.skeleton_config) onto.selection = lm.skeleton_config->selection;
  MotionWithGaps out{ConformToSkeleton(lm.motion, onto), ConformMask(lm.motion, missing, onto)};
  out.motion = Motion(skeleton, out.motion.fps(), out.motion.positions());
  if (std::abs(out.motion.fps() - fps) > 1e-6 * fps) {
    std::fprintf(stderr, "note: resampling %s from %.6g Hz to the model's %.6g Hz\n", path.c_str(),
                 out.motion.fps(), fps);
    const Motion mask_motion(skeleton, out.motion.fps(),
                             std::vector<float>(out.missing.begin(), out.missing.end()));
    const Motion resampled_mask = Resample(mask_motion, fps);
    out.motion = Resample(out.motion, fps);
    out.missing.assign(resampled_mask.positions().size(), 0);
    for (size_t i = 0; i < out.missing.size(); ++i)
      out.missing[i] = resampled_mask.positions()[i] > 0.0f;
  }
  for (size_t k = 0; k < mask_specs.size(); ++k) {
    std::vector<uint8_t> m;
    try {
      m = MaskFromSpec(mask_specs[k], *skeleton, out.motion.num_frames(), seed + k);
    } catch (const std::invalid_argument& e) {
      throw FormatError(path + ": " + e.what());
    }
    for (size_t i = 0; i < m.size(); ++i) out.missing[i] |= m[i];
  }
  // Missing values hold 0 from here on (whatever the file or a mask covered).
  std::vector<float> pos = out.motion.positions();
  for (size_t i = 0; i < pos.size(); ++i) {
    if (out.missing[i]) pos[i] = 0.0f;
  }
  out.motion = Motion(skeleton, out.motion.fps(), std::move(pos));
  return out;
}

}  // namespace motionfork::app
