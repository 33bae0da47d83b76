// Benchmark: the public C++ API's Model::Predict on a batch of histories, one thread: the time
// the Python module's predict() of the same batch is compared with (bench/python_api.py).
//
//   bench_api_predict MODEL_DIR HISTORY [--batch B] [-k K] [--repeats R] [--stdin]
//
// HISTORY: a motion file (e.g. from `motionfork synth walk`); the batch is B copies of it shifted
// by 1 mm each (as bench/python_api.py builds it). Prints the median of R timed batches (after one
// warm-up) in milliseconds, as "median_ms <value>". --stdin: after the warm-up, times one batch
// per line read from standard input and prints its milliseconds (a caller interleaves its own
// timings with these, call by call).
#include <motionfork/motionfork.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  motionfork::UseFastBlasKernels(argv);
  if (argc < 3 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    std::fprintf(stderr,
                 "usage: bench_api_predict MODEL_DIR HISTORY [--batch B] [-k K] [--repeats R]\n");
    return argc < 3 ? 2 : 0;
  }
  int batch = 16, k = 50, repeats = 10;
  bool from_stdin = false;
  for (int i = 3; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--stdin")) {
      from_stdin = true;
      continue;
    }
    if (i + 1 >= argc) break;
    if (!std::strcmp(argv[i], "--batch"))
      batch = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "-k"))
      k = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--repeats"))
      repeats = std::atoi(argv[++i]);
  }
  try {
    motionfork::LoadOptions lo;
    lo.threads = 1;
    const motionfork::Model model = motionfork::Model::Load(argv[1], lo);
    const std::vector<float> history = model.ReadMotion(argv[2]);
    std::vector<std::vector<float>> histories(batch, history);
    for (int b = 0; b < batch; ++b)
      for (float& v : histories[b]) v += 0.001f * b;
    motionfork::PredictOptions o;
    o.k = k;
    auto run = [&] {
      size_t values = 0;
      for (const auto& h : histories) values += model.Predict(h, o).positions.size();
      return values;
    };
    run();  // warm-up
    if (from_stdin) {
      std::printf("ready\n");
      std::fflush(stdout);
      for (int c; (c = std::getchar()) != EOF;) {
        if (c != '\n') continue;
        const auto t0 = std::chrono::steady_clock::now();
        run();
        std::printf("%.3f\n",
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                        .count());
        std::fflush(stdout);
      }
      return 0;
    }
    std::vector<double> ms;
    for (int r = 0; r < repeats; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      run();
      ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    std::printf("batch %d, k %d, %d repeats: median_ms %.3f\n", batch, k, repeats,
                ms[ms.size() / 2]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_api_predict: %s\n", e.what());
    return 2;
  }
  return 0;
}
