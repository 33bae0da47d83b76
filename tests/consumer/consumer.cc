// The consumer test's program: only <motionfork/motionfork.h>, linked as motionfork::api.
//   consumer BUNDLE HISTORY   prints what it loaded, predicted and checked, one fact a line.
#include <motionfork/motionfork.h>

#include <algorithm>
#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer BUNDLE HISTORY\n");
    return 2;
  }
  try {
    const motionfork::Model model = motionfork::Model::Load(argv[1]);
    std::printf("config_dir: %s\n", model.config_dir().c_str());
    std::printf("constraints: %s\n", model.constraint_set().c_str());
    std::printf("joints: %zu\n", model.joint_names().size());
    std::printf("first part: %s\n", model.parts().front().name.c_str());

    const std::vector<float> history = model.ReadMotion(argv[2]);
    motionfork::PredictOptions options;
    options.k = 4;
    options.fixed_parts = {model.parts().front().name};
    const motionfork::Futures f = model.Predict(history, options);
    std::printf("futures: %d x %d frames x %d joints\n", f.k, f.frames, f.joints);

    // Joints of the fixed first part: the same in every future.
    bool same = true;
    for (const std::string& joint : model.parts().front().joints) {
      const auto j = std::find(model.joint_names().begin(), model.joint_names().end(), joint) -
                     model.joint_names().begin();
      for (int k = 1; k < f.k; ++k) {
        for (int t = 0; t < f.frames; ++t) {
          for (int a = 0; a < 3; ++a) {
            const size_t i = (static_cast<size_t>(t) * f.joints + j) * 3 + a;
            same = same && f.sample(k)[i] == f.sample(0)[i];
          }
        }
      }
    }
    std::printf("fixed part identical: %s\n", same ? "yes" : "no");

    int valid = 0;
    for (const motionfork::SampleCheck& c : model.Check(f)) valid += c.valid;
    std::printf("checked: %d valid of %d\n", valid, f.k);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
  return 0;
}
