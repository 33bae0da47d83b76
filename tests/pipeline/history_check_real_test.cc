// The plausibility gate on real Bandai histories with the shipped model (models/bandai: angle
// ranges, prior, HG-VAE): how many real histories it doubts (validation windows cut from the
// training clips, where its bounds were chosen, and the test split), and how many broken ones it
// catches (a wrong unit, a wrong up axis, exchanged sides, a joint read from the wrong place).
#include <catch2/catch.hpp>
#include <cstdio>
#include <map>
#include <set>

#include "bundle/generator_bundle.h"
#include "bundle/hgvae_bundle.h"
#include "config/config_paths.h"
#include "config/protocol_config.h"
#include "config/rig_config.h"
#include "config/skeleton_config.h"
#include "dataset/dataset.h"
#include "generator/inference/forecaster.h"
#include "imputation/hgvae_model.h"
#include "pipeline/history_check.h"
#include "rig/joint_mapping.h"
#include "test_support.h"
#include "validity/pose_validator.h"

using namespace motionfork;
using namespace motionfork::pipeline;

namespace {

enum Breakage { kNone, kMillimetres, kZUp, kSidesExchanged, kJointMisplaced, kCount };
const char* kBreakageName[] = {"as recorded", "millimetres read as metres", "Z up read as Y up",
                               "left/right exchanged", "Hand_L read at Foot_L"};

Motion Broken(const Motion& m, Breakage b) {
  const Skeleton& s = m.skeleton();
  const int J = s.num_joints();
  std::vector<float> p = m.positions();
  const int hand = s.Index("Hand_L"), foot = s.Index("Foot_L");
  for (int t = 0; t < m.num_frames(); ++t) {
    for (int j = 0; j < J; ++j) {
      float* out = p.data() + (static_cast<size_t>(t) * J + j) * 3;
      const float* a = m.at(t, b == kSidesExchanged ? s.Mirror(j) : j);
      if (b == kJointMisplaced && j == hand) a = m.at(t, foot);
      const float k = b == kMillimetres ? 1000.0f : 1.0f;
      out[0] = k * a[0];
      out[1] = k * (b == kZUp ? -a[2] : a[1]);
      out[2] = k * (b == kZUp ? a[1] : a[2]);
    }
  }
  return Motion(m.skeleton_ptr(), m.fps(), std::move(p));
}

struct Tally {
  int windows = 0, doubted = 0;
  std::map<std::string, int> kinds;  // "scale", "axis", ... -> windows
};

// The Bandai protocol's dataset as the shipped model knows it.
struct Bandai {
  explicit Bandai(const std::string& data)
      : protocol(
            LoadProtocolConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "protocols", "bandai"))),
        ds(LoadDataset(protocol,
                       LoadSkeletonConfig(ResolveConfigPath(MOTIONFORK_CONFIG_DIR, "skeletons",
                                                            protocol.skeleton)),
                       data, Options())) {}
  static DatasetLoadOptions Options() {
    DatasetLoadOptions o;
    o.cache_dir = testing::TestCacheDir();
    return o;
  }
  const std::string model = std::string(MOTIONFORK_SOURCE_DIR) + "/models/bandai";
  ProtocolOptions protocol;
  Dataset ds;
};

}  // namespace

TEST_CASE("the gate rarely doubts real Bandai histories and catches broken ones") {
  const std::string data = testing::SharedDataDir("data/bandai");
  if (data.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  const Bandai b(data);
  const std::string& model = b.model;
  const Dataset& ds = b.ds;
  const SkeletonConfig& sc = b.ds.skeleton;
  const PoseValidator judge = PoseValidator::FromBundle(model, sc.skeleton, b.protocol.fps);
  const HgvaeModel scorer = LoadHgvaeModel(model + "/hgvae");
  const std::vector<std::string> roles =
      RolesOfSkeleton(*sc.skeleton, LoadRigConventions(MOTIONFORK_CONFIG_DIR)).roles;
  const int t_his = 15, stride = 60;

  // Validation: every tenth training clip; test: the test split. Each a window every `stride`.
  Tally tally[2][kCount];
  const std::vector<int> train = ds.ClipIndices(Split::kTrain), test = ds.ClipIndices(Split::kTest);
  for (int part = 0; part < 2; ++part) {
    std::vector<int> clips;
    if (part == 0) {
      for (size_t i = 0; i < train.size(); i += 10) clips.push_back(train[i]);
    } else {
      clips = test;
    }
    for (int c : clips) {
      const Motion& m = ds.clips[static_cast<size_t>(c)].motion;
      for (int start = 0; start + t_his <= m.num_frames(); start += stride) {
        const Motion window = m.Slice(start, start + t_his);
        for (int b = 0; b < kCount; ++b) {
          const Motion h = Broken(window, static_cast<Breakage>(b));
          const HistoryCheck got =
              CheckHistory(h, judge.Score(h.positions().data(), t_his), judge, &scorer, roles, "y");
          Tally& t = tally[part][b];
          ++t.windows;
          t.doubted += !got.doubts.empty();
          std::set<std::string> kinds;
          for (const std::string& d : got.doubts) kinds.insert(d.substr(0, d.find(':')));
          for (const std::string& k : kinds) ++t.kinds[k];
        }
      }
    }
  }
  for (int part = 0; part < 2; ++part) {
    for (int b = 0; b < kCount; ++b) {
      const Tally& t = tally[part][b];
      std::printf("%s, %s: %d of %d windows doubted (%.2f%%)", part ? "test" : "validation",
                  kBreakageName[b], t.doubted, t.windows, 100.0 * t.doubted / t.windows);
      for (const auto& [k, n] : t.kinds) std::printf("; %s %d", k.c_str(), n);
      std::printf("\n");
    }
  }
  const Tally* test_tally = tally[1];
  CHECK(test_tally[kNone].windows > 500);
  CHECK(test_tally[kNone].doubted <= test_tally[kNone].windows / 50);  // at most 2% of real ones
  for (int b = kMillimetres; b < kCount; ++b) {
    INFO(kBreakageName[b]);
    CHECK(test_tally[b].doubted >= test_tally[b].windows * 99 / 100);
  }
}

TEST_CASE("the shipped model's futures of real Bandai test histories: which judge each fails") {
  const std::string data = testing::SharedDataDir("data/bandai");
  if (data.empty()) {
    WARN("SKIPPED: ../shared/data/bandai not found");
    return;
  }
  const Bandai b(data);
  const std::string& model = b.model;
  const Dataset& ds = b.ds;
  const SkeletonConfig& sc = b.ds.skeleton;
  const Forecaster forecaster = LoadForecaster(model);
  const PoseValidator judge = PoseValidator::FromBundle(model, sc.skeleton, b.protocol.fps);
  const int t_his = forecaster.config().generator.t_his,
            t_pred = forecaster.config().generator.t_pred;
  const size_t future = static_cast<size_t>(t_pred) * sc.skeleton->num_joints() * 3;
  ForecastRequest request;
  request.k = 10;
  int futures = 0, valid = 0, angles = 0, prior = 0;
  // The first history of every second test clip.
  const std::vector<int> test = ds.ClipIndices(Split::kTest);
  for (size_t i = 0; i < test.size(); i += 2) {
    const Motion& m = ds.clips[static_cast<size_t>(test[i])].motion;
    if (m.num_frames() < t_his) continue;
    const Forecast f = forecaster.Predict(m, 0, request);
    for (int k = 0; k < f.k; ++k) {
      const SampleValidity v = judge.Score(f.futures.data() + k * future, t_pred);
      ++futures;
      valid += v.valid;
      angles += v.violating_frames > 0;
      prior += !v.prior_ok;
    }
  }
  std::printf(
      "shipped model, %d futures (10 per history, %d test histories): %d valid (%.1f%%); %d "
      "outside the angle ranges, %d above the prior's bound\n",
      futures, futures / 10, valid, 100.0 * valid / futures, angles, prior);
  CHECK(futures >= 1000);
  // Repaired futures stay inside the angle ranges; the prior's bound rejects only a few.
  CHECK(angles <= futures / 100);
  CHECK(valid >= futures * 9 / 10);
}
