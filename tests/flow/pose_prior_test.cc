// PosePrior and its training on synthetic motions: NLL goes down, save -> load is exact,
// interrupted + resumed training equals uninterrupted training, bad input gets clear errors.
#include "flow/pose_prior.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "bundle/prior_bundle.h"
#include "core/error.h"
#include "core/limbs.h"
#include "flow/catch_torch.h"
#include "flow/flow_module.h"
#include "flow/prior_data.h"
#include "flow/trainer.h"
#include "io/file_util.h"
#include "test_support.h"
#include "torch_util/threads.h"

using namespace motionfork;

namespace {

// 24 walking clips of the test humanoid (each its own phases), 4 of them the test split.
Dataset SyntheticDataset(int clips = 24, int frames = 200) {
  Dataset ds;
  ds.protocol.name = "synthetic";
  ds.protocol.fps = 30;
  ds.skeleton.skeleton = ds.skeleton.source = testing::MakeHumanoid();
  for (int c = 0; c < clips; ++c) {
    Clip clip;
    clip.name = "walk_" + std::to_string(c);
    clip.split = c < clips - 4 ? Split::kTrain : Split::kTest;
    const Motion m = testing::MakeWalkingMotion(frames, 30.0, 100 + c);
    clip.motion = Motion(ds.skeleton.skeleton, 30.0, m.positions());
    ds.clips.push_back(std::move(clip));
  }
  return ds;
}

PriorConfig SmallConfig(int epochs = 4) {
  PriorConfig c;
  c.training.epochs = epochs;
  c.training.constant_epochs = 1;
  c.training.batch_size = 256;
  c.training.held_out_share = 0.1;
  c.training.seed = 3;
  c.training.min_steps = 0;  // the epochs as given
  return c;
}

std::vector<float> Weights(const PosePrior& p) {
  std::vector<float> out;
  for (const auto& [name, t] : p.module()->OrderedParameters()) {
    const torch::Tensor c = t.detach().contiguous();
    out.insert(out.end(), c.data_ptr<float>(), c.data_ptr<float>() + c.numel());
  }
  return out;
}

}  // namespace

TEST_CASE("training lowers the held-out NLL on synthetic walking poses") {
  PinThreads(1);
  const Dataset ds = SyntheticDataset();
  const PriorConfig config = SmallConfig(6);
  const PriorData data = MakePriorData(ds, config.training);
  CHECK(data.held_out_clips.size() == 2);  // 10% of 20 training clips
  CHECK(data.train.size() == 18 * 200);
  CHECK(data.test.size() == 4 * 200);
  PosePrior prior(ds.skeleton.skeleton, config);
  const double before = MeanNll(prior, data.held_out);
  int epochs_seen = 0;
  PriorTrainCallbacks cb;
  cb.progress = [&](const PriorTrainProgress& p) { epochs_seen += p.epoch_done; };
  const PriorTrainOutcome out = TrainPosePrior(prior, data, "", cb);
  CHECK(out.completed);
  CHECK(epochs_seen == 6);
  const PriorTrainingSummary& y = prior.summary();
  REQUIRE(y.held_out_nll.size() == 6);
  WARN("synthetic held-out NLL " << before << " before training, " << y.held_out_nll.front()
                                 << " after epoch 1, " << y.held_out_nll.back()
                                 << " after epoch 6; test " << y.test_nll);
  CHECK(y.held_out_nll.back() < before - 20);
  CHECK(y.held_out_nll.back() < y.held_out_nll.front());
  CHECK(y.train_nll.back() < y.train_nll.front());
  CHECK(std::isfinite(y.test_nll));
  CHECK(y.held_out_nll_q50 <= y.held_out_nll_q90);
  CHECK(y.held_out_nll_q90 <= y.held_out_nll_q99);
  CHECK(prior.bone_lengths() == data.bone_lengths);

  // Sampling: the Metropolis-Hastings chain moves normalised flow samples to where the prior puts
  // real poses.
  auto median_nll = [&](const Motion& m) {
    std::vector<double> lp = prior.LogProb(m);
    std::sort(lp.begin(), lp.end());
    return -lp[lp.size() / 2];
  };
  const double raw = median_nll(prior.Sample(400, 1, 1.0, {}, 30.0, 0));
  const double chain = median_nll(prior.Sample(400, 1, 1.0, {}, 30.0, 400));
  WARN("median NLL of samples: raw flow samples normalised "
       << raw << ", after 400 MH steps " << chain << ", real held-out " << y.held_out_nll_q50);
  CHECK(chain < raw);
  CHECK(chain < y.held_out_nll_q90);
}

TEST_CASE("the learning-rate schedule is GSPS's: constant, then linear decay per epoch") {
  PriorTrainOptions o;  // 25 epochs, 5 constant, lr 1e-2
  CHECK(PriorLearningRate(o, 0) == 1e-2);
  CHECK(PriorLearningRate(o, 5) == 1e-2);
  CHECK(PriorLearningRate(o, 6) == Approx(1e-2 * (1 - 1.0 / 21)));
  CHECK(PriorLearningRate(o, 24) == Approx(1e-2 * (1 - 19.0 / 21)));
}

TEST_CASE("the schedule reaches training.min_steps on small data; a still-falling run is told") {
  PriorTrainOptions o;  // 25 epochs, 5 constant, at least 1,500 steps
  const PriorSchedule bandai = MakePriorSchedule(o, 62);  // 1,550 steps: as configured
  CHECK((bandai.epochs == 25 && bandai.constant_epochs == 5 && !bandai.raised));
  const PriorSchedule humaneva = MakePriorSchedule(o, 1);  // 3,596 frames, batch 4,096
  CHECK((humaneva.epochs == 1500 && humaneva.constant_epochs == 300 && humaneva.raised));
  const PriorSchedule some = MakePriorSchedule(o, 7);  // 1,500 / 7 -> 215 epochs (1,505 steps)
  CHECK((some.epochs == 215 && some.constant_epochs == 43));
  o.min_steps = 0;
  CHECK(MakePriorSchedule(o, 1).epochs == 25);

  double gain = 0;
  CHECK(HeldOutStillFalling({5, 3, 2, 1.5, 1.2, 1.0, 0.8, 0.6, 0.4, 0.2}, &gain));
  CHECK(gain == Approx(1.0 - 0.2));  // best before the last 2 epochs: 1.0
  CHECK_FALSE(HeldOutStillFalling({5, 3, 2, 1, 1, 1, 1, 1, 1, 0.95}, &gain));
  CHECK_FALSE(HeldOutStillFalling({5, 3}));  // too few epochs to tell

  // Training: 200 frames in one batch = 1 step an epoch; 2 epochs raised to min_steps 40.
  PinThreads(1);
  const Dataset ds = SyntheticDataset(6, 60);
  PriorConfig config = SmallConfig(2);
  config.training.batch_size = 4096;
  config.training.held_out_share = 0.25;
  config.training.min_steps = 40;
  const PriorData data = MakePriorData(ds, config.training);
  REQUIRE(data.train.size() < 4096);
  PosePrior prior(ds.skeleton.skeleton, config);
  int epochs_seen = 0;
  PriorTrainCallbacks cb;
  cb.progress = [&](const PriorTrainProgress& p) {
    epochs_seen += p.epoch_done;
    CHECK(p.epochs == 40);
  };
  const PriorTrainOutcome out = TrainPosePrior(prior, data, "", cb);
  CHECK((out.completed && out.epochs == 40 && out.epochs_raised));
  CHECK(epochs_seen == 40);
  CHECK(prior.summary().epochs_completed == 40);
  // 40 full-batch steps at lr 1e-2 leave the flow far from converged: said so.
  CHECK(out.still_falling);
  CHECK(out.recent_gain > kPriorStillFallingNats);
}

TEST_CASE("save -> load gives identical log-probs, config, skeleton, summary and bone lengths") {
  PinThreads(1);
  testing::TempDir dir;
  const Dataset ds = SyntheticDataset(10, 100);
  const PriorData data = MakePriorData(ds, SmallConfig(2).training);
  PosePrior prior(ds.skeleton.skeleton, SmallConfig(2));
  prior.set_skeleton_config("bandai");
  prior.mutable_summary().protocol = "synthetic";
  TrainPosePrior(prior, data, "");
  SavePosePrior(prior, dir.path().string());
  const PosePrior loaded = LoadPosePrior(dir.path().string());
  CHECK(loaded.LogProbDirections(data.test.directions) ==
        prior.LogProbDirections(data.test.directions));
  CHECK(Weights(loaded) == Weights(prior));
  CHECK(FormatFlowConfig(loaded.config()) == FormatFlowConfig(prior.config()));
  CHECK(loaded.skeleton().SameStructure(prior.skeleton()));
  CHECK(loaded.skeleton().name() == prior.skeleton().name());
  CHECK(loaded.skeleton_config() == "bandai");
  CHECK(loaded.bone_lengths() == prior.bone_lengths());
  CHECK(loaded.summary().held_out_nll == prior.summary().held_out_nll);
  CHECK(loaded.summary().held_out_nll_q99 == prior.summary().held_out_nll_q99);
  CHECK(loaded.summary().protocol == "synthetic");
  CHECK(loaded.num_parameters() == 10586);
  // The bundle is small: ~10.6k float32 parameters.
  CHECK(std::filesystem::file_size(dir.file("weights.npy")) < 50000);
}

TEST_CASE("a damaged or foreign bundle is refused with the file named") {
  testing::TempDir dir;
  PosePrior prior(testing::MakeHumanoid(), SmallConfig());
  SavePosePrior(prior, dir.path().string());
  const std::string yaml = ReadFileBytes(dir.file("prior.yaml"));
  const std::string weights = ReadFileBytes(dir.file("weights.npy"));
  auto rewrite = [&](const std::string& y, const std::string& w) {
    WriteFileAtomically(dir.file("prior.yaml"), y);
    WriteFileAtomically(dir.file("weights.npy"), w);
  };
  auto replaced = [](std::string s, const std::string& from, const std::string& to) {
    const size_t at = s.find(from);
    REQUIRE(at != std::string::npos);
    return s.replace(at, from.size(), to);
  };
  // Weights of another bundle (one float changed).
  std::string other = weights;
  other[other.size() - 3] ^= 0x10;
  rewrite(yaml, other);
  CHECK_THROWS_WITH(LoadPosePrior(dir.path().string()), Catch::Contains("checksum"));
  // A config that describes another network (4 layers) than the stored parameters.
  rewrite(replaced(yaml, "layers: 3", "layers: 4"), weights);
  CHECK_THROWS_WITH(LoadPosePrior(dir.path().string()), Catch::Contains("parameters"));
  // Not a prior.
  rewrite(replaced(yaml, "format: motionfork-flow-prior", "format: something-else"), weights);
  CHECK_THROWS_AS(LoadPosePrior(dir.path().string()), FormatError);
  // A newer version.
  rewrite(replaced(yaml, "version: 1", "version: 7"), weights);
  CHECK_THROWS_WITH(LoadPosePrior(dir.path().string()), Catch::Contains("version 7"));
  // A typo'd key.
  rewrite(replaced(yaml, "  epochs:", "  epocs:"), weights);
  CHECK_THROWS_WITH(LoadPosePrior(dir.path().string()),
                    Catch::Contains("unknown key 'training.epocs'"));
  // A folder without a bundle.
  testing::TempDir empty;
  CHECK_THROWS_WITH(LoadPosePrior(empty.path().string()), Catch::Contains("prior.yaml"));
  rewrite(yaml, weights);
  CHECK_NOTHROW(LoadPosePrior(dir.path().string()));
}

TEST_CASE("interrupted and resumed training equals uninterrupted training, bit for bit") {
  PinThreads(1);
  const Dataset ds = SyntheticDataset(12, 120);
  const PriorConfig config = SmallConfig(3);
  const PriorData data = MakePriorData(ds, config.training);
  testing::TempDir a, b;

  PosePrior straight(ds.skeleton.skeleton, config);
  CHECK(TrainPosePrior(straight, data, a.file("checkpoint.pt")).completed);

  PosePrior first(ds.skeleton.skeleton, config);
  int epochs_done = 0;
  int steps_after = 0;
  PriorTrainCallbacks stop_in_epoch_2;
  stop_in_epoch_2.progress = [&](const PriorTrainProgress& p) {
    epochs_done += p.epoch_done;
    if (epochs_done == 1 && !p.epoch_done) ++steps_after;
  };
  stop_in_epoch_2.stop_requested = [&] { return steps_after >= 2; };  // mid-epoch 2
  const PriorTrainOutcome stopped =
      TrainPosePrior(first, data, b.file("checkpoint.pt"), stop_in_epoch_2);
  CHECK_FALSE(stopped.completed);
  REQUIRE(std::filesystem::exists(b.file("checkpoint.pt")));

  PosePrior resumed(ds.skeleton.skeleton, config);  // a fresh process, as after Ctrl-C
  const PriorTrainOutcome out = TrainPosePrior(resumed, data, b.file("checkpoint.pt"));
  CHECK(out.completed);
  CHECK(out.resumed_from_epoch == 1);
  CHECK(Weights(resumed) == Weights(straight));
  CHECK(resumed.summary().held_out_nll == straight.summary().held_out_nll);
  CHECK(resumed.summary().train_nll == straight.summary().train_nll);

  // Same seed, same data: deterministic. Another config: the checkpoint is refused.
  PriorConfig other = config;
  other.training.learning_rate = 5e-3;
  PosePrior wrong(ds.skeleton.skeleton, other);
  CHECK_THROWS_WITH(TrainPosePrior(wrong, data, b.file("checkpoint.pt")),
                    Catch::Contains("another config") && Catch::Contains("learning_rate"));
  // A damaged checkpoint is a FormatError naming the file.
  WriteFileAtomically(b.file("checkpoint.pt"), "not a checkpoint");
  PosePrior damaged(ds.skeleton.skeleton, config);
  CHECK_THROWS_AS(TrainPosePrior(damaged, data, b.file("checkpoint.pt")), FormatError);
}

TEST_CASE("bad input gets a clear error: joint count, NaN, zero-length bone, other skeleton") {
  PosePrior prior(testing::MakeHumanoid(), SmallConfig());
  // Wrong joint count.
  auto five = std::make_shared<const Skeleton>(
      Skeleton::FromParents("five", {"a", "b", "c", "d", "e"}, {-1, 0, 1, 2, 3}));
  const Motion short_motion(five, 30.0, std::vector<float>(5 * 3 * 2, 0.0f));
  CHECK_THROWS_WITH(prior.LogProb(short_motion), Catch::Contains("expected 17 joints, got 5"));
  // Another skeleton with the same joint count.
  const Skeleton& h = prior.skeleton();
  std::vector<std::string> names = h.joint_names();
  names[10] = "Nose";
  auto other =
      std::make_shared<const Skeleton>(Skeleton::FromParents("h36m_like", names, h.parents()));
  const Motion walk = testing::MakeWalkingMotion(3);
  const Motion on_other(other, 30.0, walk.positions());
  CHECK_THROWS_WITH(prior.LogProb(on_other),
                    Catch::Contains("joint 10") && Catch::Contains("'Nose'"));
  // Zero-length bone: the frame and the bone are named.
  std::vector<float> p = walk.positions();
  for (int a = 0; a < 3; ++a) p[(2 * 17 + 2) * 3 + a] = p[(2 * 17 + 1) * 3 + a];  // frame 2
  CHECK_THROWS_WITH(prior.LogProb(Motion(walk.skeleton_ptr(), 30.0, p)),
                    Catch::Contains("frame 2") && Catch::Contains("LowerLeg_R"));
  // NaN and non-unit directions.
  std::vector<float> d = ToLimbs(walk).directions;
  d[48 + 7] = std::nanf("");
  CHECK_THROWS_WITH(prior.LogProbDirections(d),
                    Catch::Contains("pose 1, limb 2") && Catch::Contains("NaN"));
  d = ToLimbs(walk).directions;
  d[0] *= 3;
  CHECK_THROWS_WITH(prior.LogProbDirections(d), Catch::Contains("unit direction"));
  d.pop_back();
  CHECK_THROWS_WITH(prior.LogProbDirections(d), Catch::Contains("multiple of 48"));
  // A skeleton without a tree.
  CHECK_THROWS_AS(
      PosePrior(std::make_shared<const Skeleton>(Skeleton::Anonymous(17)), SmallConfig()),
      std::invalid_argument);
  CHECK_NOTHROW(prior.LogProb(walk));
}

TEST_CASE(
    "forward/inverse round-trip through the facade, and samples have the requested bone lengths") {
  PinThreads(1);
  const PosePrior prior(testing::MakeHumanoid(), SmallConfig());
  const std::vector<float> d = ToLimbs(testing::MakeWalkingMotion(20)).directions;
  const std::vector<float> back = prior.Inverse(prior.Forward(d));
  float worst = 0;
  for (size_t i = 0; i < d.size(); ++i) worst = std::max(worst, std::abs(back[i] - d[i]));
  CHECK(worst < 1e-4f);

  std::vector<double> lengths(16);
  for (int k = 0; k < 16; ++k) lengths[k] = 0.1 + 0.01 * k;
  const Motion s = prior.Sample(50, 7, 1.0, lengths);
  REQUIRE(s.num_frames() == 50);
  const Limbs limbs = ToLimbs(s);
  for (int t = 0; t < 50; ++t) {
    for (int k = 0; k < 16; ++k)
      CHECK(limbs.lengths[t * 16 + k] == Approx(lengths[k]).epsilon(1e-4));
    for (int a = 0; a < 3; ++a) CHECK(s.at(t, 0)[a] == 0.0f);
  }
  CHECK(prior.Sample(50, 7, 1.0, lengths).positions() == s.positions());  // seeded
  CHECK(prior.Sample(50, 8, 1.0, lengths).positions() != s.positions());
  CHECK_THROWS_AS(prior.Sample(0, 1), std::invalid_argument);
  CHECK_THROWS_AS(prior.Sample(3, 1, 1.0, {1.0, 2.0}), std::invalid_argument);
}

TEST_CASE("flow config: defaults are GSPS's, every key round-trips, errors name file and key") {
  const PriorConfig defaults = ParseFlowConfig("model: {}\n", "x.yaml");
  CHECK(defaults.model.num_layers == 3);
  CHECK(defaults.training.epochs == 25);
  CHECK(defaults.training.constant_epochs == 5);
  CHECK(defaults.training.batch_size == 4096);
  CHECK(defaults.training.learning_rate == 1e-2);
  CHECK(defaults.training.weight_decay == 1e-3);
  CHECK(defaults.training.min_steps == 1500);
  const PriorConfig shipped =
      LoadFlowConfig(std::string(MOTIONFORK_CONFIG_DIR) + "/models/flow_prior.yaml");
  CHECK(FormatFlowConfig(shipped) == FormatFlowConfig(defaults));
  PriorConfig c = SmallConfig();
  c.training.learning_rate = 0.1 / 3;
  c.training.seed = 12345678901234ull;
  CHECK(FormatFlowConfig(ParseFlowConfig(FormatFlowConfig(c), "x")) == FormatFlowConfig(c));
  CHECK_THROWS_WITH(ParseFlowConfig("training:\n  lr: 0.1\n", "my.yaml"),
                    Catch::Contains("my.yaml:line 2") && Catch::Contains("training.lr"));
  CHECK_THROWS_WITH(ParseFlowConfig("training:\n  batch_size: 0\n", "my.yaml"),
                    Catch::Contains("training.batch_size = 0"));
  CHECK_THROWS_WITH(ParseFlowConfig("training:\n  epochs: many\n", "my.yaml"),
                    Catch::Contains("line 2") && Catch::Contains("epochs"));
}
