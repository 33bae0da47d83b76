// predict_example: the public API end to end. Loads a model bundle, reads a history, predicts K
// futures with one body part fixed, checks them against the model's angle ranges and prints a
// summary.
//
//   predict_example BUNDLE HISTORY [K] [FIXED_PART]
//     BUNDLE      model bundle folder (model.yaml + generator.pt), e.g. models/bandai
//     HISTORY     motion file (.bvh, .npy, .csv); its last history_frames() frames are used
//     K           futures to sample (default 10)
//     FIXED_PART  body part all futures share (default: the first part, e.g. legs); "none" = none
#include <motionfork/motionfork.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

namespace {

// Largest distance (metres) of a joint in any future from the same joint in future 0.
float SpreadFromFirst(const motionfork::Futures& f, int joint) {
  float spread = 0;
  for (int k = 1; k < f.k; ++k) {
    for (int t = 0; t < f.frames; ++t) {
      const float* a = f.sample(0) + (static_cast<size_t>(t) * f.joints + joint) * 3;
      const float* b = f.sample(k) + (static_cast<size_t>(t) * f.joints + joint) * 3;
      spread = std::max(spread, std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
    }
  }
  return spread;
}

int Run(int argc, char** argv) {
  const char* usage =
      "usage: %s BUNDLE HISTORY [K] [FIXED_PART]\n"
      "  Loads a model bundle, reads a history (.bvh, .npy, .csv), predicts K futures (default\n"
      "  10) with FIXED_PART shared by all (default: the first part; \"none\": none), checks them\n"
      "  against the bundle's angle ranges and prints a summary.\n";
  if (argc == 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    std::printf(usage, argv[0]);
    return 0;
  }
  if (argc < 3 || argc > 5) {
    std::fprintf(stderr, usage, argv[0]);
    return 2;
  }
  const motionfork::Model model = motionfork::Model::Load(argv[1]);
  std::printf("model: %s, protocol %s, %zu joints, %d history -> %d future frames at %g Hz\n",
              argv[1], model.protocol().c_str(), model.joint_names().size(), model.history_frames(),
              model.future_frames(), model.fps());
  std::printf("constraints: %s\n",
              model.constraint_set().empty() ? "(none)" : model.constraint_set().c_str());

  const std::vector<float> history = model.ReadMotion(argv[2]);
  const size_t frame_size = model.joint_names().size() * 3;
  std::printf("history: %s, %zu frames", argv[2], history.size() / frame_size);
  if (!model.constraint_set().empty()) {
    const motionfork::SampleCheck h = model.CheckMotion(history);
    std::printf(", %zu outside an angle range", h.violating_frames.size());
  }
  std::printf("\n");

  motionfork::PredictOptions options;
  options.k = argc > 3 ? std::atoi(argv[3]) : 10;
  options.seed = 0;
  const std::string fixed = argc > 4 ? argv[4] : model.parts().front().name;
  if (fixed != "none") options.fixed_parts = {fixed};
  const motionfork::Futures futures = model.Predict(history, options);
  std::printf("futures: %d x %d frames, fixed part: %s\n", futures.k, futures.frames,
              fixed.c_str());

  // Control: a fixed part varies less across the futures than the free ones.
  for (const motionfork::Part& part : model.parts()) {
    float spread = 0;
    for (const std::string& joint : part.joints) {
      const auto it = std::find(model.joint_names().begin(), model.joint_names().end(), joint);
      spread = std::max(spread, SpreadFromFirst(futures, int(it - model.joint_names().begin())));
    }
    std::printf("part %-8s %2zu joints, largest distance from future 0: %.3f m\n",
                part.name.c_str(), part.joints.size(), spread);
  }

  if (!model.constraint_set().empty()) {
    const std::vector<motionfork::SampleCheck> checks = model.Check(futures);
    int valid = 0;
    for (size_t i = 0; i < checks.size(); ++i) {
      const motionfork::SampleCheck& c = checks[i];
      valid += c.valid;
      std::printf("future %2zu: %s", i, c.valid ? "valid" : "invalid");
      if (!c.valid) {
        std::printf(" (%zu frames outside a range, %zu with an undefined angle",
                    c.violating_frames.size(), c.undefined_frames.size());
        for (size_t n = 0; n < c.violated_constraints.size() && n < 3; ++n) {
          std::printf("%s %s", n ? "," : ";", c.violated_constraints[n].c_str());
        }
        std::printf(")");
      }
      std::printf("\n");
    }
    std::printf("valid futures: %d of %d\n", valid, futures.k);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  motionfork::UseFastBlasKernels(argv);
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "predict_example: %s\n", e.what());
    return 1;
  }
}
