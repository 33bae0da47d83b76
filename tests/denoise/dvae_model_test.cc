// Training, fine-tuning, bundles and denoising on a tiny Motion-DVAE trained in code.
#include "denoise/dvae_model.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bundle/dvae_bundle.h"
#include "core/error.h"
#include "core/motion_noise.h"
#include "denoise/denoise_metrics.h"
#include "denoise/refiner_blend.h"
#include "io/file_util.h"
#include "test_support.h"
#include "tiny_dvae.h"
#include "torch_catch.h"

using namespace motionfork;
using Catch::Contains;

namespace {

namespace fs = std::filesystem;

// One tiny prior + denoiser for the whole file.
const std::string& TinyDir() {
  static testing::TempDir dir;
  static const bool done = [] {
    testing::WriteTinyDvaeBundles(dir.file("m"), 4, 3);
    return true;
  }();
  (void)done;
  static const std::string path = dir.file("m");
  return path;
}

std::vector<double> Column(const std::string& csv, const std::string& name) {
  std::ifstream in(csv);
  std::string header, line, cell;
  std::getline(in, header);
  std::stringstream hs(header);
  int col = -1, i = 0;
  while (std::getline(hs, cell, ',')) {
    if (cell == name) col = i;
    ++i;
  }
  REQUIRE(col >= 0);
  std::vector<double> out;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    for (int k = 0; k <= col; ++k) std::getline(ls, cell, ',');
    out.push_back(std::stod(cell));
  }
  return out;
}

std::vector<torch::Tensor> Weights(const std::string& dir) {
  DvaeManifest m;
  DvaeNet net = LoadDvaeBundle(dir, &m);
  std::vector<torch::Tensor> out;
  for (const auto& p : net->parameters()) out.push_back(p.detach().clone());
  return out;
}

}  // namespace

TEST_CASE("dvae training lowers the loss and fine-tuning changes only the encoder side") {
  const std::string& dir = TinyDir();
  const std::vector<double> loss = Column(dir + "/prior/log.csv", "loss");
  REQUIRE(loss.size() == 4);
  CHECK(loss.back() < loss.front());
  const std::vector<double> ft = Column(dir + "/denoiser/log.csv", "loss");
  REQUIRE(ft.size() == 3);
  CHECK(ft.back() < ft.front());
  DvaeManifest pm, dm;
  DvaeNet prior = LoadDvaeBundle(dir + "/prior", &pm), den = LoadDvaeBundle(dir + "/denoiser", &dm);
  CHECK_FALSE(pm.finetuned);
  CHECK(dm.finetuned);
  CHECK(dm.finetune_noise == std::vector<std::string>{"gaussian:0.05", "jitter:0.03"});
  const auto pd = prior->DecoderParameters(), dd = den->DecoderParameters();
  for (size_t i = 0; i < pd.size(); ++i) CHECK(torch::equal(pd[i], dd[i]));
  const auto pe = prior->EncoderParameters(), de = den->EncoderParameters();
  int changed = 0;
  for (size_t i = 0; i < pe.size(); ++i) changed += !torch::equal(pe[i], de[i]);
  CHECK(changed == static_cast<int>(pe.size()));
}

TEST_CASE("dvae training and fine-tuning resume exactly where they stopped") {
  testing::TempDir tmp;
  const DvaeTrainConfig cfg = testing::TinyDvaeConfig(3, 2);
  const DvaeData data = testing::TinyDvaeData();
  const DvaeManifest base = testing::TinyDvaeBase(cfg);
  TrainDvae(cfg, base, data, tmp.file("a"), {});
  TrainDvae(cfg, base, data, tmp.file("b"), {}, 2);
  CHECK(Column(tmp.file("b") + "/log.csv", "loss").size() == 2);
  const DvaeTrainSummary s = TrainDvae(cfg, base, data, tmp.file("b"), {});
  CHECK(s.first_epoch == 2);
  const auto wa = Weights(tmp.file("a")), wb = Weights(tmp.file("b"));
  for (size_t i = 0; i < wa.size(); ++i) CHECK(torch::equal(wa[i], wb[i]));
  FinetuneDvae(cfg, tmp.file("a"), data, tmp.file("fa"), {});
  FinetuneDvae(cfg, tmp.file("a"), data, tmp.file("fb"), {}, 1);
  FinetuneDvae(cfg, tmp.file("a"), data, tmp.file("fb"), {});
  CHECK(Column(tmp.file("fa") + "/log.csv", "held_out_loss") ==
        Column(tmp.file("fb") + "/log.csv", "held_out_loss"));
  const auto fa = Weights(tmp.file("fa")), fb = Weights(tmp.file("fb"));
  for (size_t i = 0; i < fa.size(); ++i) CHECK(torch::equal(fa[i], fb[i]));
  CHECK_THROWS_WITH(FinetuneDvae(cfg, tmp.file("fa"), data, tmp.file("fc"), {}),
                    Contains("fine-tuned already"));
}

TEST_CASE(
    "denoising: same seed same output, any length, optimisation mode leaves the bundle unchanged") {
  const DvaeModel model = LoadDvaeModel(TinyDir() + "/denoiser");
  const Motion clean = testing::MakeWalkingMotion(47, 30, 999);
  const Motion noisy = AddNoise(clean, ParseNoiseSpec("gaussian:0.05"), 4);
  DenoiseOptions o = model.manifest().denoise;
  DenoiseStats stats;
  const Motion a = DenoiseMotion(model, noisy, o, &stats);
  CHECK(a.num_frames() == 47);
  CHECK(stats.windows == 9);  // starts 0, 5, ..., 35 and the last at 37
  CHECK(stats.noise_std.size() == static_cast<size_t>(model.joints()));
  CHECK(DenoiseMotion(model, noisy, o).positions() == a.positions());
  o.seed = 5;
  CHECK(DenoiseMotion(model, noisy, o).positions() != a.positions());
  o.seed = model.manifest().denoise.seed;
  for (float v : a.positions()) REQUIRE(std::isfinite(v));
  // Short sequences are one window of their own length.
  CHECK(DenoiseMotion(model, noisy.Slice(0, 4), o).num_frames() == 4);
  // Optimisation mode: a different result, and afterwards regression mode is what it was.
  DenoiseOptions opt = o;
  opt.mode = DenoiseMode::kOptimisation;
  const Motion b = DenoiseMotion(model, noisy, opt);
  CHECK(b.positions() != a.positions());
  CHECK(DenoiseMotion(model, noisy, o).positions() == a.positions());
  // Means only, and the decoder's frames alone.
  o.samples = 0;
  CHECK(DenoiseMotion(model, noisy, o).positions() == DenoiseMotion(model, noisy, o).positions());
  o.fuse = false;
  CHECK(DenoiseMotion(model, noisy, o).positions() != a.positions());
}

TEST_CASE("denoising on several threads gives the same output as on one, in both modes") {
  DvaeModel model = LoadDvaeModel(TinyDir() + "/denoiser");
  // Sequences of several lengths: several chunks (work items) in regression mode, one per
  // sequence in optimisation mode.
  std::vector<std::vector<float>> noisy;
  for (int frames : {47, 4, 6, 31}) {
    noisy.push_back(AddNoise(testing::MakeWalkingMotion(frames, 30, 100 + frames),
                             ParseNoiseSpec("gaussian:0.05"), 4)
                        .positions());
  }
  DenoiseOptions reg = model.manifest().denoise, opt = reg;
  reg.mode = DenoiseMode::kRegression;
  opt.mode = DenoiseMode::kOptimisation;
  DenoiseStats s1, s3;
  const auto reg_one = model.Denoise(noisy, reg, &s1);
  const auto opt_one = model.Denoise(noisy, opt);
  model.set_threads(3);
  CHECK(model.Denoise(noisy, reg, &s3) == reg_one);
  CHECK(s3.noise_std == s1.noise_std);
  CHECK(model.Denoise(noisy, opt) == opt_one);
  // The threads' copies are the bundle's weights: regression mode is unchanged afterwards.
  CHECK(model.Denoise(noisy, reg) == reg_one);
  CHECK(opt_one != reg_one);
}

TEST_CASE("denoising refuses what it cannot use, naming it") {
  const DvaeModel model = LoadDvaeModel(TinyDir() + "/denoiser");
  const DenoiseOptions o = model.manifest().denoise;
  std::vector<float> bad = testing::MakeWalkingMotion(20).positions();
  bad[3 * model.joints() * 5 + 4] = std::nanf("");
  CHECK_THROWS_WITH(model.Denoise({bad}, o), Contains("frame 5") && Contains("not finite"));
  CHECK_THROWS_WITH(model.Denoise({std::vector<float>(10, 0.0f)}, o), Contains("joints x 3"));
  const Motion at60(testing::MakeHumanoid(), 60.0, testing::MakeWalkingMotion(20).positions());
  CHECK_THROWS_WITH(DenoiseMotion(model, at60, o), Contains("60") && Contains("30"));
  testing::TempDir tmp;
  fs::create_directories(tmp.file("b"));
  fs::copy_file(TinyDir() + "/denoiser/dvae.yaml", tmp.file("b") + "/dvae.yaml");
  CHECK_THROWS_WITH(LoadDvaeModel(tmp.file("b")), Contains("dvae.pt") && Contains("missing"));
  WriteFileAtomically(tmp.file("b") + "/dvae.pt", "garbage");
  CHECK_THROWS_AS(LoadDvaeModel(tmp.file("b")), FormatError);
}

TEST_CASE(
    "the refiner learns to remove noise, travels in the bundle and denoises in refiner mode") {
  testing::TempDir tmp;
  DvaeTrainConfig cfg = testing::TinyDvaeConfig(1, 1);
  cfg.refiner.model = {16, 20, 5, {1, 2}, 3};
  cfg.refiner.training.epochs = 3;
  cfg.refiner.training.windows_per_epoch = 256;
  cfg.refiner.noise = {"gaussian:0.08"};
  const DvaeData data = testing::TinyDvaeData();
  const DvaeTrainSummary s = RefineDvae(cfg, TinyDir() + "/denoiser", data, tmp.file("r"), {});
  CHECK(s.epochs_done == 3);
  const std::vector<double> input = Column(tmp.file("r") + "/log.csv", "held_out_input_cm"),
                            refined = Column(tmp.file("r") + "/log.csv", "held_out_refined_cm");
  REQUIRE(refined.size() == 3);
  CHECK(refined.back() < 0.8 * input.back());
  // Without an acceleration term the held-out loss (early stopping's) is the joint error.
  CHECK(Column(tmp.file("r") + "/log.csv", "held_out_loss") == refined);
  DvaeModel model = LoadDvaeModel(tmp.file("r"));
  CHECK(model.manifest().refiner.channels == 16);
  CHECK(model.manifest().denoise.mode == DenoiseMode::kRefiner);
  // The rest of the network is the bundle it started from: regression mode is unchanged.
  const DvaeModel before = LoadDvaeModel(TinyDir() + "/denoiser");
  const Motion clean = testing::MakeWalkingMotion(47, 30, 999);
  const Motion noisy = AddNoise(clean, ParseNoiseSpec("gaussian:0.05"), 4);
  DenoiseOptions reg = before.manifest().denoise;
  CHECK(DenoiseMotion(model, noisy, reg).positions() ==
        DenoiseMotion(before, noisy, reg).positions());
  // Refiner mode: less error than the input, the same on several threads, any length.
  const DenoiseOptions o = model.manifest().denoise;
  DenoiseStats stats;
  const Motion a = DenoiseMotion(model, noisy, o, &stats);
  CHECK(stats.windows == 7);  // starts 0, 5, ..., 25 and the last at 27
  CHECK(stats.noise_std.empty());
  CHECK(MeanJointError(a.positions(), clean.positions()) <
        0.7 * MeanJointError(noisy.positions(), clean.positions()));
  model.set_threads(3);
  CHECK(DenoiseMotion(model, noisy, o).positions() == a.positions());
  CHECK(DenoiseMotion(model, noisy.Slice(0, 4), o).num_frames() == 4);
  // A bundle without a refiner refuses the mode.
  CHECK_THROWS_WITH(DenoiseMotion(before, noisy, o), Contains("dvae refine"));
  // The run ends by fitting the blend weights on held-out clips; the output blends by them and
  // without them is the refiner's own.
  REQUIRE(model.manifest().refiner_blend.weights.size() == static_cast<size_t>(kRefinerBlendBins));
  CHECK(model.manifest().refiner_blend.weights == s.refiner_blend.weights);
  CHECK(model.manifest().refiner_blend.sigma == s.refiner_blend.sigma);
  CHECK(model.manifest().refiner_blend.smooth == s.refiner_blend.smooth);
  {  // the output smoothing round-trips; absent, it is 0
    DvaeManifest m2 = model.manifest();
    m2.refiner_blend.smooth = 0.75;
    std::ofstream(tmp.file("smooth.yaml")) << FormatDvaeManifest(m2);
    CHECK(LoadDvaeManifest(tmp.file("smooth.yaml")).refiner_blend.smooth == 0.75);
    m2.refiner_blend.smooth = 0;
    CHECK(FormatDvaeManifest(m2).find("smooth:") == std::string::npos);
    m2.refiner_blend.accel_bound = 2.5;  // the smoothing chosen per motion
    std::ofstream(tmp.file("bound.yaml")) << FormatDvaeManifest(m2);
    CHECK(LoadDvaeManifest(tmp.file("bound.yaml")).refiner_blend.accel_bound == 2.5);
    std::string text = FormatDvaeManifest(m2);
    text.replace(text.find("accel_bound: 2.5"), 16, "accel_bound: -1");
    std::ofstream(tmp.file("bad_bound.yaml")) << text;
    CHECK_THROWS_WITH(LoadDvaeManifest(tmp.file("bad_bound.yaml")),
                      Contains("accel_bound in [0, 100]"));
    m2.refiner_blend.accel_bound = 0;
    CHECK(FormatDvaeManifest(m2).find("accel_bound:") == std::string::npos);
  }
  {  // the roughness measure round-trips; an unknown one is refused, named, with the choices
    DvaeManifest m2 = model.manifest();
    m2.refiner_blend.roughness = Roughness::kSavitzkyGolayMedian;
    std::string text = FormatDvaeManifest(m2);
    std::ofstream(tmp.file("median.yaml")) << text;
    CHECK(LoadDvaeManifest(tmp.file("median.yaml")).refiner_blend.roughness ==
          Roughness::kSavitzkyGolayMedian);
    text.replace(text.find("savitzky-golay-median"), 21, "mean-of-joints");
    std::ofstream(tmp.file("bad_roughness.yaml")) << text;
    CHECK_THROWS_WITH(LoadDvaeManifest(tmp.file("bad_roughness.yaml")),
                      Contains("refiner_blend.roughness") && Contains("savitzky-golay-median") &&
                          Contains("'mean-of-joints'"));
  }
  {  // the outlier repair round-trips; absent, there is none; a bad one is refused, named
    DvaeManifest m2 = model.manifest();
    m2.refiner_blend.outliers = {3, 4.5};
    std::ofstream(tmp.file("outliers.yaml")) << FormatDvaeManifest(m2);
    const OutlierRepair back = LoadDvaeManifest(tmp.file("outliers.yaml")).refiner_blend.outliers;
    CHECK(back.half_window == 3);
    CHECK(back.deviations == 4.5);
    std::string text = FormatDvaeManifest(m2);
    text.replace(text.find("half_window: 3"), 14, "half_window: 0");
    std::ofstream(tmp.file("bad_outliers.yaml")) << text;
    CHECK_THROWS_WITH(LoadDvaeManifest(tmp.file("bad_outliers.yaml")),
                      Contains("refiner_blend.outliers: expected half_window in [1, 1000]"));
    m2.refiner_blend.outliers = {};
    CHECK(FormatDvaeManifest(m2).find("outliers:") == std::string::npos);
  }
  // Refiner mode repairs the outliers the blend names, refines the repaired motion and blends.
  DenoiseOptions raw = o;
  raw.refiner_blend = false;
  const RefinerBlend& blend = model.manifest().refiner_blend;
  const std::vector<float> in =
      RepairOutliers(noisy.positions(), noisy.num_joints(), blend.outliers);
  const Motion r = DenoiseMotion(model, Motion(noisy.skeleton_ptr(), noisy.fps(), in), raw);
  CHECK(a.positions() == BlendRefined(in, r.positions(), noisy.num_joints(), blend));
  {  // the blend fitted again alone: the same weights file, the same summary
    const DvaeTrainSummary again = RefitRefinerBlend(cfg, tmp.file("r"), data, tmp.file("refit"));
    CHECK(again.refiner_blend.weights == blend.weights);
    CHECK(again.refiner_blend.outliers.half_window == blend.outliers.half_window);
    CHECK(ReadFileBytes(tmp.file("refit") + "/dvae.pt") ==
          ReadFileBytes(tmp.file("r") + "/dvae.pt"));
    CHECK(LoadDvaeModel(tmp.file("refit")).manifest().refiner_blend.weights == blend.weights);
    CHECK_THROWS_WITH(RefitRefinerBlend(cfg, TinyDir() + "/denoiser", data, tmp.file("no")),
                      Contains("no refiner"));
  }
  // With one, the loss adds the acceleration error (positive on noisy windows).
  cfg.refiner.accel_weight = 2;
  cfg.refiner.training.epochs = 1;
  RefineDvae(cfg, TinyDir() + "/denoiser", data, tmp.file("a"), {});
  const std::vector<double> loss = Column(tmp.file("a") + "/log.csv", "held_out_loss"),
                            error = Column(tmp.file("a") + "/log.csv", "held_out_refined_cm");
  REQUIRE(loss.size() == 1);
  CHECK(loss[0] > error[0] + 0.01);
}
