// The generator's temporal floor (issues 27 and 28): its futures live in the first n_pre DCT
// coefficients of the t_his + t_pred padded frames (generator/model/generator_net.cc), so no
// sample can follow motion faster than those coefficients hold. Projects the true windows of a
// protocol onto the first n coefficients, for several n, and prints the ADE / FDE (the protocol's
// pose-vector norms, root-relative) and the history's error the projection alone leaves, overall
// and per action. Windows: VALIDATION clips by default (every 10th training clip in the
// dataset's order; never the test split, which --test shows for information). Cache: as motionfork.
//   bench_dct_floor ../shared/data/bandai [--protocol bandai] [--test] [--n 8,10,12,14,16,20]
#include <Eigen/Dense>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "config/protocol_dataset.h"
#include "core/dct.h"
#include "eval/test_set.h"
#include "io/cache_dir.h"

using namespace motionfork;

namespace {

struct Sums {
  double ade = 0, fde = 0, history = 0;
  int windows = 0;
};

// [T, D] root-relative pose vectors of window i: the history's (root dropped) then the future's.
Eigen::MatrixXd WindowPoses(const TestSet& s, int i) {
  const int J = s.num_joints(), D = s.pose_dims, T = s.t_his + s.t_pred;
  Eigen::MatrixXd w(T, D);
  const float* h = s.history(i);
  for (int t = 0; t < s.t_his; ++t) {
    const float* frame = h + static_cast<size_t>(t) * J * 3;
    for (int j = 1; j < J; ++j)
      for (int a = 0; a < 3; ++a) w(t, 3 * (j - 1) + a) = frame[3 * j + a] - frame[a];
  }
  const float* f = s.future(i);
  for (int t = 0; t < s.t_pred; ++t)
    for (int d = 0; d < D; ++d) w(s.t_his + t, d) = f[static_cast<size_t>(t) * D + d];
  return w;
}

void Add(Sums* s, const Eigen::MatrixXd& error, int t_his) {
  const Eigen::VectorXd norms = error.rowwise().norm();
  const int T = static_cast<int>(norms.size());
  s->ade += norms.tail(T - t_his).mean();
  s->fde += norms(T - 1);
  s->history += norms.head(t_his).mean();
  ++s->windows;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_dct_floor DATA [--protocol NAME] [--test] [--n 8,10,...]\n");
    return 2;
  }
  std::string protocol = "bandai";
  bool test = false;
  std::vector<int> counts = {8, 10, 12, 14, 16, 20};
  for (int a = 2; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--protocol" && a + 1 < argc) {
      protocol = argv[++a];
    } else if (arg == "--test") {
      test = true;
    } else if (arg == "--n" && a + 1 < argc) {
      counts.clear();
      std::stringstream list(argv[++a]);
      for (std::string item; std::getline(list, item, ',');) counts.push_back(std::stoi(item));
    } else {
      std::fprintf(stderr, "bench_dct_floor: unknown argument '%s'\n", arg.c_str());
      return 2;
    }
  }
  const Dataset ds =
      LoadProtocolDataset({protocol, argv[1], "", MOTIONFORK_BENCH_CONFIG_DIR, CacheDir("")});
  std::vector<const Clip*> clips;
  const std::vector<int> chosen = ds.ClipIndices(test ? Split::kTest : Split::kTrain);
  for (size_t i = 0; i < chosen.size(); ++i) {
    if (test || i % 10 == 9) clips.push_back(&ds.clips[chosen[i]]);
  }
  const TestSet s = BuildTestSet(clips, ds.protocol);
  const int T = s.t_his + s.t_pred;
  std::printf("%s: %zu %s clips, %d windows of %d + %d frames\n", ds.protocol.name.c_str(),
              clips.size(), test ? "test" : "validation (every 10th training)", s.num_windows(),
              s.t_his, s.t_pred);
  std::vector<Eigen::MatrixXd> windows;
  for (int i = 0; i < s.num_windows(); ++i) windows.push_back(WindowPoses(s, i));
  std::printf("%-6s %-24s %8s %8s %8s %8s\n", "n_pre", "action", "windows", "ADE", "FDE",
              "history");
  for (const int n : counts) {
    const Eigen::MatrixXd d = DctMatrix(T).topRows(n);
    const Eigen::MatrixXd projection = d.transpose() * d;  // [T, T]
    Sums all;
    std::map<int, Sums> per_action;
    for (int i = 0; i < s.num_windows(); ++i) {
      const Eigen::MatrixXd error = projection * windows[i] - windows[i];
      Add(&all, error, s.t_his);
      Add(&per_action[s.action[i]], error, s.t_his);
    }
    auto row = [&](const std::string& name, const Sums& x) {
      std::printf("%-6d %-24s %8d %8.4f %8.4f %8.4f\n", n, name.c_str(), x.windows,
                  x.ade / x.windows, x.fde / x.windows, x.history / x.windows);
    };
    row("all", all);
    for (const auto& [a, x] : per_action) row(s.actions[a].empty() ? "-" : s.actions[a], x);
  }
  return 0;
}
