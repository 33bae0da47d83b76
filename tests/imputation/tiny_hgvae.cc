#include "imputation/tiny_hgvae.h"

#include "bundle/hgvae_bundle.h"
#include "test_support.h"

namespace motionfork::testing {

HgvaeData TinyHgvaeData(int clips, int frames) {
  HgvaeData d;
  d.coords = 48;
  for (int c = 0; c < clips; ++c) {
    HgvaeClips& dst = c % 4 == 3 ? d.held_out : d.train;
    dst.poses.push_back(PoseVectorsWithoutRoot(MakeWalkingMotion(frames, 30.0, 100 + c)));
    dst.labels.push_back(-1);
  }
  return d;
}

HgvaeTrainConfig TinyHgvaeConfig(int window, int epochs) {
  HgvaeTrainConfig c;
  c.name = "tiny";
  c.protocol = "bandai";
  c.model.levels = {{1, 16}, {8, 16}, {0, 16}};
  c.model.width = 32;
  c.model.window = window;
  c.model = ResolveHgvaeOptions(c.model, 48, window);
  c.training.epochs = epochs;
  c.training.windows_per_epoch = 1024;
  c.training.batch_size = 64;
  c.training.kl_warmup_epochs = 2;
  c.training.held_out_windows = 64;
  c.training.learning_rate = 3e-3;
  return c;
}

void WriteTinyHgvaeBundle(const std::string& dir, int window, int epochs) {
  const HgvaeTrainConfig cfg = TinyHgvaeConfig(window, epochs);
  HgvaeManifest base;
  base.protocol = "bandai";
  base.fps = 30;
  base.skeleton = MakeHumanoid()->ToSpec();
  base.impute = cfg.impute;
  base.ood_k = cfg.ood_k;
  base.ood_score = cfg.ood_score;
  TrainHgvae(cfg, base, TinyHgvaeData(), dir, {});
}

}  // namespace motionfork::testing
