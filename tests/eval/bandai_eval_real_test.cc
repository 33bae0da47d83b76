// The Bandai test split (../shared/data/bandai) with both baselines, against the figures an
// independent implementation of the protocol measured (K = 50, threshold 0.5).
#include <catch2/catch.hpp>

#include "bandai_real_data.h"
#include "eval/baselines.h"
#include "eval/evaluate.h"
#include "eval/test_set.h"
#include "test_support.h"

using namespace motionfork;

namespace {

// Third decimal: |ours - reference| < 0.0005 m.
void CheckFigures(const Figures& f, double apd, double ade, double fde, double mmade,
                  double mmfde) {
  CHECK(f.apd == Approx(apd).margin(5e-4));
  CHECK(f.ade == Approx(ade).margin(5e-4));
  CHECK(f.fde == Approx(fde).margin(5e-4));
  CHECK(f.mmade == Approx(mmade).margin(5e-4));
  CHECK(f.mmfde == Approx(mmfde).margin(5e-4));
}

}  // namespace

TEST_CASE("bandai test split: zero-velocity and nearest neighbours match the reference figures") {
  const std::string data = testing::SharedDataDir("data/bandai");
  if (data.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  testing::TempDir cache;
  const testing::RealBandai bandai = testing::LoadRealBandai(data, cache.path().string());
  const ProtocolOptions& p = bandai.protocol;
  const Dataset& ds = bandai.dataset;
  REQUIRE(p.multimodal_threshold == 0.5);
  REQUIRE(p.keep_singleton_sets);
  std::vector<const Clip*> test;
  std::vector<const Motion*> train;
  for (const Clip& c : ds.clips) {
    if (c.split == Split::kTest) test.push_back(&c);
    if (c.split == Split::kTrain) train.push_back(&c.motion);
  }
  REQUIRE(test.size() == 314);
  TestSet ts = BuildTestSet(test, p);
  REQUIRE(ts.num_windows() == 2547);
  CHECK(!AttachMultimodalSets(&ts, p.multimodal_threshold, cache.path().string(), p.name));
  CHECK(AttachMultimodalSets(&ts, p.multimodal_threshold, cache.path().string(), p.name));

  EvalOptions o;  // K = 50, seed 0
  REQUIRE(o.num_samples == 50);
  ZeroVelocityPredictor zv(ts.skeleton, p.t_his, p.t_pred);
  const EvalResult z = Evaluate(zv, ts, o);
  CHECK(z.overall.windows == 2547);
  CHECK(z.overall.apd == 0.0);
  CheckFigures(z.overall, 0.0, 0.263, 0.337, 0.350, 0.407);

  NearestNeighbourPredictor nn(train, p.t_his, p.t_pred);
  CHECK(nn.num_training_windows() == 29064);
  const EvalResult n = Evaluate(nn, ts, o);
  CheckFigures(n.overall, 2.507, 0.297, 0.268, 0.383, 0.319);
}
