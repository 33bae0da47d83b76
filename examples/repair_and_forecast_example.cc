// repair_and_forecast_example: the whole pipeline through the public API, no command involved.
// Reads a history, marks a limb as missing in its last frames (as an occluded marker would be),
// fills it with an HG-VAE, predicts K futures, checks them against the model's angle ranges and
// prior, and writes the prediction files and the first future as BVH.
//
//   repair_and_forecast_example BUNDLE IMPUTER HISTORY OUT [K]
//     BUNDLE    model bundle folder, e.g. models/bandai
//     IMPUTER   HG-VAE bundle folder on the same skeleton, e.g. models/bandai/hgvae
//     HISTORY   motion file (.bvh, .npy, .csv)
//     OUT       output path: OUT.npy + OUT.json (as `motionfork predict`), OUT_00.bvh
//     K         futures to sample (default 10)
#include <motionfork/motionfork.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>
#include <vector>

namespace {

int Run(int argc, char** argv) {
  if (argc == 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    std::printf("usage: %s BUNDLE IMPUTER HISTORY OUT [K]\n", argv[0]);
    return 0;
  }
  if (argc < 5 || argc > 6) {
    std::fprintf(stderr, "usage: %s BUNDLE IMPUTER HISTORY OUT [K]\n", argv[0]);
    return 2;
  }
  std::printf("motionfork %s (headers %s)\n", motionfork::Version(), MOTIONFORK_VERSION_STRING);
  const motionfork::Model model = motionfork::Model::Load(argv[1]);
  const motionfork::Imputer imputer = motionfork::Imputer::Load(argv[2]);
  if (imputer.joint_names() != model.joint_names()) {
    std::fprintf(stderr, "%s and %s are on different skeletons\n", argv[1], argv[2]);
    return 2;
  }
  std::vector<float> history = model.ReadMotion(argv[3]);
  const int J = static_cast<int>(model.joint_names().size());
  const int T = static_cast<int>(history.size() / (3 * J));

  // 1. Damage: the last joint of the last part (e.g. a hand) and its parent missing for the last
  // history_frames() / 2 frames.
  const motionfork::Part& part = model.parts().back();
  std::vector<int> hidden;
  for (int j = 0; j < J; ++j) {
    if (model.joint_names()[j] == part.joints.back()) {
      hidden = {j, model.parents()[j]};
    }
  }
  const int from = T - model.history_frames() / 2;
  for (int t = from; t < T; ++t) {
    for (int j : hidden) {
      for (int c = 0; c < 3; ++c) {
        history[(static_cast<size_t>(t) * J + j) * 3 + c] = std::numeric_limits<float>::quiet_NaN();
      }
    }
  }
  // 2. Repair.
  const motionfork::Imputed filled = imputer.Impute(history);
  std::printf("imputed %d missing values (joints %s and %s, frames %d..%d)\n",
              filled.missing_values, model.joint_names()[hidden[0]].c_str(),
              model.joint_names()[hidden[1]].c_str(), from, T - 1);
  // 3. Forecast.
  motionfork::PredictOptions options;
  options.k = argc > 5 ? std::atoi(argv[5]) : 10;
  const motionfork::Futures futures = model.Predict(filled.positions, options);
  std::printf("futures: %d x %d frames after %d history frames\n", futures.k, futures.frames,
              futures.history_frames);
  // 4. Check.
  if (!model.constraint_set().empty()) {
    int valid = 0;
    for (const motionfork::SampleCheck& s : model.Check(futures)) valid += s.valid;
    std::printf("valid futures: %d of %d (angle ranges '%s')\n", valid, futures.k,
                model.constraint_set().c_str());
  }
  if (model.has_prior()) {
    const std::vector<double> nll = model.PriorNll(futures.Sequence(0));
    double mean = 0;
    for (double v : nll) mean += v / nll.size();
    std::printf("prior NLL of sample 0: %.2f nats per pose\n", mean);
  }
  // 5. Export.
  const std::string out = argv[4];
  const std::string base = model.WritePrediction(out, futures, options);
  motionfork::BvhExportOptions bvh;
  bvh.sample = 0;
  const std::vector<std::string> files = model.ExportBvh(out + "_00.bvh", futures, bvh);
  std::printf("wrote %s.npy, %s.json and %s\n", base.c_str(), base.c_str(), files.at(0).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  motionfork::UseFastBlasKernels(argv);
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
