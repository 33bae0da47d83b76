// BVH parse throughput, single thread, in MB/s of BVH text (hierarchy + motion + FK).
//
// Usage: bench_bvh [--frames N] [--repeat R] [--data DIR] [--no-data]
//   --frames N   frames in the synthetic Bandai-like file (22 joints x 6 channels; default 100000,
//                about 130 MB of text)
//   --repeat R   timed parses of the synthetic file; the best and median are reported (default 5)
//   --data DIR   folder with bandai-1.tar.xz and bandai-2.tar.xz (default ../shared/data/bandai
//                next to the source tree); every .bvh in them is decompressed into memory first
//                (not timed), then all are parsed once (timed)
//   --no-data    skip the archives
#include "io/bvh.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/archive.h"
#include "torch_util/blas_core.h"

namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// A BVH laid out like the Bandai files: 22 joints, 6 channels each (Xposition Yposition
// Zposition Zrotation Xrotation Yrotation), tab after the labels, numbers printed with 6
// significant digits, a trailing space on each frame line, 30 fps.
std::string MakeBandaiLike(int frames) {
  const char* names[] = {"joint_Root", "Hips",       "Spine",      "Chest",      "Neck",
                         "Head",       "Shoulder_L", "UpperArm_L", "LowerArm_L", "Hand_L",
                         "Shoulder_R", "UpperArm_R", "LowerArm_R", "Hand_R",     "UpperLeg_L",
                         "LowerLeg_L", "Foot_L",     "Toes_L",     "UpperLeg_R", "LowerLeg_R",
                         "Foot_R",     "Toes_R"};
  const int parents[] = {-1, 0,  1,  2, 3,  4,  3,  6, 7,  8,  3,
                         10, 11, 12, 1, 14, 15, 16, 1, 18, 19, 20};
  const int n = 22;
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> off(-30, 30), ang(-180, 180), small(-1, 1);
  std::vector<double> offset(3 * n);
  for (double& o : offset) o = off(rng);

  std::string s = "HIERARCHY\n";
  char buf[128];
  // Children in index order: the parents above are depth-first, so file order = index order.
  std::function<void(int, int)> write = [&](int j, int depth) {
    const std::string ind(2 * depth, ' ');
    s += ind + (j == 0 ? "ROOT " : "JOINT ") + names[j] + "\n" + ind + "{\n";
    std::snprintf(buf, sizeof buf, "%s  OFFSET %g %g %g\n", ind.c_str(), offset[3 * j],
                  offset[3 * j + 1], offset[3 * j + 2]);
    s += buf;
    s += ind + "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n";
    bool leaf = true;
    for (int k = j + 1; k < n; ++k) {
      if (parents[k] == j) {
        leaf = false;
        write(k, depth + 1);
      }
    }
    if (leaf)
      s += ind + "  End Site\n" + ind + "  {\n" + ind + "    OFFSET 0 0 0\n" + ind + "  }\n";
    s += ind + "}\n";
  };
  write(0, 0);
  s += "MOTION\nFrames:\t" + std::to_string(frames) + "\nFrame Time:\t0.0333333\n";
  for (int t = 0; t < frames; ++t) {
    for (int j = 0; j < n; ++j) {
      const double* o = &offset[3 * j];
      std::snprintf(buf, sizeof buf, "%g %g %g %g %g %g ", o[0] + small(rng), o[1] + small(rng),
                    o[2] + small(rng), ang(rng), ang(rng), ang(rng));
      s += buf;
    }
    s += "\n";
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  motionfork::UseFastBlasKernels(argv);
  int frames = 100000;
  int repeat = 5;
  bool use_data = true;
  std::string data_dir =
      (std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() / "shared" /
       "data" / "bandai")
          .string();
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--frames" && i + 1 < argc) {
      frames = std::atoi(argv[++i]);
    } else if (a == "--repeat" && i + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--data" && i + 1 < argc) {
      data_dir = argv[++i];
    } else if (a == "--no-data") {
      use_data = false;
    } else {
      std::fprintf(stderr, "usage: %s [--frames N] [--repeat R] [--data DIR] [--no-data]\n",
                   argv[0]);
      return 2;
    }
  }

  // (a) Synthetic Bandai-like file.
  const std::string text = MakeBandaiLike(frames);
  std::vector<double> times;
  long checksum = 0;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = Clock::now();
    const motionfork::Motion m = motionfork::ReadBvhText(text, "synthetic.bvh");
    times.push_back(Seconds(t0));
    checksum += m.num_frames();
  }
  std::sort(times.begin(), times.end());
  const double mb = text.size() / 1e6;
  std::printf(
      "synthetic Bandai-like: %d frames x 22 joints x 6 channels, %.1f MB; "
      "best %.3f s = %.0f MB/s, median %.3f s = %.0f MB/s (%d runs)\n",
      frames, mb, times.front(), mb / times.front(), times[times.size() / 2],
      mb / times[times.size() / 2], repeat);

  // (b) Every BVH in the shared archives, decompressed first.
  if (use_data) {
    for (const char* archive : {"bandai-1.tar.xz", "bandai-2.tar.xz"}) {
      const std::string path = data_dir + "/" + archive;
      if (!std::filesystem::exists(path)) {
        std::printf("%s: not found, skipped\n", path.c_str());
        continue;
      }
      std::vector<std::pair<std::string, std::string>> files;
      const auto d0 = Clock::now();
      motionfork::ForEachArchiveFile(
          path,
          [](const std::string& p) {
            return p.size() > 4 && p.compare(p.size() - 4, 4, ".bvh") == 0;
          },
          [&](const std::string& p, std::string_view bytes) { files.emplace_back(p, bytes); });
      const double decompress = Seconds(d0);
      size_t bytes = 0;
      long total_frames = 0;
      const auto t0 = Clock::now();
      for (const auto& [name, content] : files) {
        const motionfork::Motion m = motionfork::ReadBvhText(content, name);
        bytes += content.size();
        total_frames += m.num_frames();
      }
      const double parse = Seconds(t0);
      std::printf(
          "%s: %zu files, %ld frames, %.1f MB; decompress %.2f s (not counted), "
          "parse %.2f s = %.0f MB/s, %.0f frames/s\n",
          archive, files.size(), total_frames, bytes / 1e6, decompress, parse, bytes / 1e6 / parse,
          total_frames / parse);
    }
  }
  return checksum > 0 ? 0 : 1;
}
