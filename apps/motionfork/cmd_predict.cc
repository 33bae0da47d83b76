// motionfork predict: K futures of a history with a trained model bundle.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include "app_common.h"
#include "commands.h"
#include "core/resample.h"
#include "generator/forecaster.h"
#include "io/file_util.h"
#include "io/npy.h"
#include "motion_options.h"

namespace motionfork::app {
namespace {

struct PredictOptions {
  std::string model;
  std::string history;
  int start = -1;
  int k = 50;
  std::vector<std::string> fix;
  uint64_t seed = 0;
  std::string out;
  MotionInputOptions input;
};

void RunPredict(const PredictOptions& o, const GlobalOptions& g) {
  const Forecaster model = Forecaster::Load(o.model);
  const ModelConfig& mc = model.config();
  // Read the history; put it on the model's skeleton (by names, or through --skeleton's selection).
  LoadedMotion lm = LoadMotionInput(o.history, o.input, ConfigDir(g.config_dir));
  SkeletonConfig onto;
  onto.skeleton = model.skeleton();
  onto.source = lm.skeleton_config ? lm.skeleton_config->source : model.skeleton();
  if (lm.skeleton_config) onto.selection = lm.skeleton_config->selection;
  Motion history = ConformToSkeleton(lm.motion, onto);
  history = Motion(model.skeleton(), history.fps(), history.positions());
  if (std::abs(history.fps() - mc.fps) > 1e-6 * mc.fps) {
    std::fprintf(stderr, "note: resampling the history from %.6g Hz to the model's %.6g Hz\n", history.fps(), mc.fps);
    history = Resample(history, mc.fps);
  }
  const int t_his = mc.generator.t_his;
  const int start = o.start >= 0 ? o.start : history.num_frames() - t_his;
  ForecastRequest req;
  req.k = o.k;
  req.seed = o.seed;
  req.fixed_parts = o.fix;
  const Forecast f = model.Predict(history, start, req);

  // [K, t_his + t_pred, J, 3]: each sample is the history followed by its future.
  const int T = f.t_his + f.t_pred, J = f.joints;
  NpyArray out;
  out.shape = {f.k, T, J, 3};
  out.data.resize(static_cast<size_t>(f.k) * T * J * 3);
  for (int k = 0; k < f.k; ++k) {
    float* dst = out.data.data() + static_cast<size_t>(k) * T * J * 3;
    std::copy(f.history.begin(), f.history.end(), dst);
    std::copy(f.futures.begin() + static_cast<size_t>(k) * f.t_pred * J * 3,
              f.futures.begin() + static_cast<size_t>(k + 1) * f.t_pred * J * 3, dst + f.history.size());
  }
  std::string base = o.out;
  if (base.size() > 4 && base.substr(base.size() - 4) == ".npy") base = base.substr(0, base.size() - 4);
  WriteNpy(base + ".npy", out);
  std::ostringstream j;
  j << "{\n  \"model\": \"" << o.model << "\",\n  \"protocol\": \"" << mc.protocol << "\",\n  \"history\": \""
    << o.history << "\",\n  \"start_frame\": " << start << ",\n  \"k\": " << f.k << ",\n  \"seed\": " << o.seed
    << ",\n  \"fps\": " << f.fps << ",\n  \"t_his\": " << f.t_his << ",\n  \"t_pred\": " << f.t_pred
    << ",\n  \"joints\": [";
  for (int i = 0; i < J; ++i) j << (i ? ", " : "") << "\"" << model.skeleton()->joint_name(i) << "\"";
  j << "],\n  \"fixed_parts\": [";
  for (size_t i = 0; i < o.fix.size(); ++i) j << (i ? ", " : "") << "\"" << o.fix[i] << "\"";
  j << "],\n  \"array\": \"" << std::filesystem::path(base + ".npy").filename().string()
    << "\",\n  \"shape\": [" << f.k << ", " << T << ", " << J << ", 3]\n}\n";
  WriteFileAtomically(base + ".json", j.str());
  std::printf("wrote %s.npy [%d, %d, %d, 3] (history + %d futures, %.6g Hz) and %s.json\n", base.c_str(), f.k,
              T, J, f.k, f.fps, base.c_str());
}

}  // namespace

void AddPredictCommand(CLI::App& app, GlobalOptions& global) {
  auto o = std::make_shared<PredictOptions>();
  CLI::App* cmd = app.add_subcommand(
      "predict",
      "Predict K futures of a history with a trained model bundle.\n"
      "Writes OUT.npy [K, t_his + t_pred, J, 3] (each sample: the history, then its future; metres;\n"
      "the root stays where the history ended: models predict root-relative poses) and OUT.json.");
  cmd->add_option("--model", o->model, "Model bundle folder (model.yaml + generator.pt)")->required();
  cmd->add_option("--history", o->history, "Motion file holding the history (.bvh, .npy, .csv)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--start", o->start, "First history frame (default: the last t_his frames of the file)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("-k", o->k, "Futures to predict (default 50)")->check(CLI::PositiveNumber);
  cmd->add_option("--fix", o->fix,
                  "Body part whose latent all K futures share (e.g. legs: same legs, varied upper "
                  "body); repeat for several");
  cmd->add_option("--seed", o->seed, "Random seed: the same seed gives the same futures (default 0)");
  cmd->add_option("-o,--out", o->out, "Output path (OUT.npy and OUT.json are written)")->required();
  AddMotionInputOptions(cmd, &o->input);
  cmd->callback([o, &global] { RunPredict(*o, global); });
}

}  // namespace motionfork::app
