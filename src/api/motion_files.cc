// motionfork::ReadMotion, WriteMotion and Prior (include/motionfork/motionfork.h) over the
// pipeline's motion input, the motion file writers and the pose prior: this file only adapts types.
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "bundle/prior_bundle.h"
#include "config_dir.h"
#include "core/motion.h"
#include "flow/pose_prior.h"
#include "io/motion_file.h"
#include "motionfork/motionfork.h"
#include "pipeline/motion_input.h"
#include "positions.h"

namespace motionfork {

int MotionData::frames() const {
  const size_t frame = joint_names.size() * 3;
  return frame == 0 ? 0 : static_cast<int>(positions.size() / frame);
}

MotionData ReadMotion(const std::string& path, const FileReadOptions& options) {
  pipeline::MotionInputOptions in;
  in.skeleton = options.skeleton;
  in.fps = options.fps;
  in.bvh_scale = options.bvh_scale;
  in.config_dir = options.skeleton.empty() ? "" : FindConfigDir(options.config_dir);
  std::vector<uint8_t> missing;
  const pipeline::LoadedMotion loaded = pipeline::LoadMotionInput(path, in, &missing);
  const Motion& m = loaded.motion;
  MotionData out;
  out.positions = m.positions();
  for (size_t i = 0; i < out.positions.size() && i < missing.size(); ++i)
    if (missing[i]) out.positions[i] = std::numeric_limits<float>::quiet_NaN();
  out.joint_names = m.skeleton().joint_names();
  out.parents = m.skeleton().parents();
  out.fps = m.fps();
  return out;
}

void WriteMotion(const std::string& path, const MotionData& motion,
                 const FileWriteOptions& options) {
  const Motion m = MotionFromPositions(motion.joint_names, motion.parents, motion.fps,
                                       motion.positions, "WriteMotion " + path);
  BvhWriteOptions bvh;
  bvh.scale_to_metres = options.bvh_scale;
  bvh.rotation_order = options.rotation_order;
  WriteMotionFile(path, m, bvh);
}

struct Prior::Impl {
  PosePrior prior;
};

Prior::Prior(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Prior::~Prior() = default;
Prior::Prior(Prior&&) noexcept = default;
Prior& Prior::operator=(Prior&&) noexcept = default;

Prior Prior::Load(const std::string& bundle_dir) {
  return Prior(std::make_unique<Impl>(Impl{LoadPosePrior(bundle_dir)}));
}

const std::vector<std::string>& Prior::joint_names() const {
  return impl_->prior.skeleton().joint_names();
}

std::vector<double> Prior::Nll(const std::vector<float>& positions) const {
  const Motion m =
      MotionFromPositions(impl_->prior.skeleton_ptr(), 30.0, positions, "Prior::Nll: positions");
  std::vector<double> nll = impl_->prior.LogProb(m);
  for (double& v : nll) v = -v;
  return nll;
}

}  // namespace motionfork
