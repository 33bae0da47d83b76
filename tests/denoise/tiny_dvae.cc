#include "tiny_dvae.h"

#include "test_support.h"

namespace motionfork::testing {

DvaeData TinyDvaeData(int clips, int frames) {
  DvaeData d;
  d.joints = MakeHumanoid()->num_joints();
  for (int c = 0; c < clips; ++c) {
    (c % 4 == 3 ? d.held_out : d.train)
        .push_back(MakeWalkingMotion(frames, 30.0, 200 + c).positions());
  }
  return d;
}

DvaeTrainConfig TinyDvaeConfig(int epochs, int finetune_epochs) {
  DvaeTrainConfig c;
  c.name = "tiny";
  c.protocol = "bandai";
  c.model.window = 10;
  c.model.hidden = 32;
  c.model.latent = 8;
  c.model.mlp_hidden = 32;
  c.model.groups = 8;
  c.training.epochs = epochs;
  c.training.windows_per_epoch = 256;
  c.training.batch_size = 32;
  c.training.kl_anneal_epochs = 2;
  c.training.held_out_windows = 32;
  c.training.learning_rate = 3e-3;
  c.finetune.epochs = finetune_epochs;
  c.finetune.windows_per_epoch = 256;
  c.finetune.batch_size = 32;
  c.finetune.kl_anneal_epochs = 1;
  c.finetune.learning_rate = 1e-3;
  c.finetune.noise = {"gaussian:0.05", "jitter:0.03"};
  c.denoise.iterations = 3;
  c.denoise.samples = 2;
  c.denoise.stride = 5;
  return c;
}

DvaeManifest TinyDvaeBase(const DvaeTrainConfig& config) {
  DvaeManifest base;
  base.protocol = "bandai";
  base.fps = 30;
  base.skeleton = MakeHumanoid()->ToSpec();
  base.noise_prior = config.noise_prior;
  base.denoise = config.denoise;
  return base;
}

void WriteTinyDvaeBundles(const std::string& dir, int epochs, int finetune_epochs) {
  const DvaeTrainConfig cfg = TinyDvaeConfig(epochs, finetune_epochs);
  const DvaeData data = TinyDvaeData();
  TrainDvae(cfg, TinyDvaeBase(cfg), data, dir + "/prior", {});
  FinetuneDvae(cfg, dir + "/prior", data, dir + "/denoiser", {});
}

}  // namespace motionfork::testing
