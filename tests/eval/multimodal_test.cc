// Multimodal ground-truth sets and test windows on constructed datasets, checked against answers
// worked out by hand.
#include "eval/multimodal.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <set>

#include "core/error.h"
#include "eval/test_set.h"
#include "test_support.h"

using namespace motionfork;

namespace {

std::vector<int> SetOf(const MultimodalSets& s, int i) {
  return std::vector<int>(s.set(i), s.set(i) + s.set_size(i));
}

ProtocolOptions SmallProtocol() {
  ProtocolOptions p;
  p.name = "small";
  p.skeleton = "test_humanoid";
  p.fps = 30;
  p.t_his = 3;
  p.t_pred = 4;
  p.test_stride = 3;
  p.test_include_last = true;
  return p;
}

// A clip of the humanoid standing still (root at x, rest pose) whose every non-root joint is
// shifted by `shift` metres along X from frame `from` on.
Clip StillClip(const std::string& name, const std::string& action, int frames, float root_x,
               float shift, int from) {
  const Motion walk = testing::MakeWalkingMotion(1);
  std::vector<float> p;
  for (int t = 0; t < frames; ++t) {
    for (int j = 0; j < 17; ++j) {
      for (int a = 0; a < 3; ++a) {
        float v = walk.at(0, j)[a] - walk.at(0, 0)[a];
        if (a == 0) v += root_x + (j > 0 && t >= from ? shift : 0.0f);
        p.push_back(v);
      }
    }
  }
  Clip c;
  c.name = name;
  c.action = action;
  c.split = Split::kTest;
  c.motion = Motion(walk.skeleton_ptr(), 30, std::move(p));
  return c;
}

}  // namespace

TEST_CASE("multimodal sets: last poses closer than the threshold, strictly, self included") {
  // Pose vectors of 2 numbers along a line: 0, 0.3, 0.6, 1.5, and 2.0 (exactly 0.5 from 1.5).
  const std::vector<float> last = {0.0f, 0, 0.3f, 0, 0.6f, 0, 1.5f, 0, 2.0f, 0};
  const MultimodalSets s = ComputeMultimodalSets(last, 2, 0.5);
  REQUIRE(s.num_windows() == 5);
  CHECK(SetOf(s, 0) == std::vector<int>{0, 1});
  CHECK(SetOf(s, 1) == std::vector<int>{0, 1, 2});
  CHECK(SetOf(s, 2) == std::vector<int>{1, 2});
  CHECK(SetOf(s, 3) == std::vector<int>{3});  // 2.0 is 0.5 away: not < 0.5
  CHECK(SetOf(s, 4) == std::vector<int>{4});
  // Distance over the whole vector: (0.3, 0.4) is 0.5 from the origin, (0.3, 0.39) is closer.
  const MultimodalSets t = ComputeMultimodalSets({0, 0, 0.3f, 0.4f, 0.3f, 0.39f}, 2, 0.5);
  CHECK(SetOf(t, 0) == std::vector<int>{0, 2});
  CHECK(SetOf(t, 1) == std::vector<int>{1, 2});
  CHECK_THROWS_WITH(ComputeMultimodalSets({0, 0, 0}, 2, 0.5),
                    Catch::Contains("not a multiple of 2"));
  CHECK_THROWS_WITH(ComputeMultimodalSets({0, 0}, 2, 0), Catch::Contains("threshold > 0"));
}

TEST_CASE("test windows and multimodal sets of a constructed dataset") {
  // Three still clips, windows of 3 + 4 = 7 frames, stride 3, last start included:
  //  a: 10 frames -> starts 0, 3; every joint shifted by 0.2 m from frame 5 on, so window 0's last
  //     history pose (frame 2) is the rest pose and window 1's (frame 5) the shifted one;
  //  b: 7 frames -> start 0, shifted by 0.3 m from frame 0, standing 5 m away (root-relative
  //     poses ignore where the root is);
  //  c: 6 frames -> no window.
  const Clip a = StillClip("a", "wave", 10, 0.0f, 0.2f, 5);
  const Clip b = StillClip("b", "bow", 7, 5.0f, 0.3f, 0);
  const Clip c = StillClip("c", "wave", 6, 0.0f, 0.0f, 0);
  TestSet ts = BuildTestSet({&a, &b, &c}, SmallProtocol());
  REQUIRE(ts.num_windows() == 3);
  CHECK(ts.windows[0].clip == 0);
  CHECK(ts.windows[1].start == 3);
  CHECK(ts.windows[2].clip == 1);
  CHECK(ts.pose_dims == 48);
  CHECK(ts.actions == std::vector<std::string>{"bow", "wave"});
  CHECK(ts.action == std::vector<int>{1, 1, 0});
  // Histories are world positions as recorded; futures root-relative pose vectors.
  CHECK(ts.history(2)[0] == Approx(5.0f));
  CHECK(ts.future(0)[0] == Approx(a.motion.at(3, 1)[0] - a.motion.at(3, 0)[0]));
  CHECK(ts.future(1)[3 * 48 + 45] == Approx(a.motion.at(9, 16)[0] - a.motion.at(9, 0)[0]));

  // Last history poses differ from the rest pose by 16 joints x shift along X: distance
  // 4 x shift. Window 0: 0; window 1: 0.8; window 2: 1.2. Pairwise: 0-1 0.8, 0-2 1.2, 1-2 0.4.
  REQUIRE(!AttachMultimodalSets(&ts, 0.5, "", "small"));
  CHECK(SetOf(ts.multimodal, 0) == std::vector<int>{0});
  CHECK(SetOf(ts.multimodal, 1) == std::vector<int>{1, 2});
  CHECK(SetOf(ts.multimodal, 2) == std::vector<int>{1, 2});
  REQUIRE(!AttachMultimodalSets(&ts, 0.9, "", "small"));
  CHECK(SetOf(ts.multimodal, 0) == std::vector<int>{0, 1});
  CHECK(SetOf(ts.multimodal, 1) == std::vector<int>{0, 1, 2});

  // DLow's rule (last start excluded): clip a gives start 0 only (3 is T - 7), b none.
  ProtocolOptions dlow = SmallProtocol();
  dlow.test_include_last = false;
  CHECK(BuildTestSet({&a, &b, &c}, dlow).num_windows() == 1);
}

TEST_CASE("an empty split and mismatched clips are clear errors") {
  const Clip c = StillClip("c", "wave", 6, 0.0f, 0.0f, 0);
  CHECK_THROWS_WITH(BuildTestSet({&c}, SmallProtocol()),
                    Catch::Contains("no test windows") && Catch::Contains("7 frames"));
  CHECK_THROWS_WITH(BuildTestSet({}, SmallProtocol()), Catch::Contains("0 clips"));
  Clip other = StillClip("other", "wave", 8, 0.0f, 0.0f, 0);
  other.motion = Motion(std::make_shared<const Skeleton>(Skeleton::Anonymous(17)), 30,
                        other.motion.positions());
  const Clip a = StillClip("a", "wave", 8, 0.0f, 0.0f, 0);
  CHECK_THROWS_WITH(BuildTestSet({&a, &other}, SmallProtocol()), Catch::Contains("'other'"));
  Clip fast = StillClip("fast", "wave", 8, 0.0f, 0.0f, 0);
  fast.motion = Motion(fast.motion.skeleton_ptr(), 60, fast.motion.positions());
  CHECK_THROWS_WITH(BuildTestSet({&fast}, SmallProtocol()), Catch::Contains("60"));
}

TEST_CASE("multimodal sets are cached under a key of the threshold and every last pose") {
  testing::TempDir dir;
  const Clip a = StillClip("a", "wave", 10, 0.0f, 0.2f, 5);
  const Clip b = StillClip("b", "bow", 7, 5.0f, 0.3f, 0);
  TestSet ts = BuildTestSet({&a, &b}, SmallProtocol());
  CHECK(!AttachMultimodalSets(&ts, 0.5, dir.path().string(), "small"));  // computed, written
  const MultimodalSets first = ts.multimodal;
  CHECK(AttachMultimodalSets(&ts, 0.5, dir.path().string(), "small"));  // read back
  CHECK(ts.multimodal.offsets == first.offsets);
  CHECK(ts.multimodal.members == first.members);
  CHECK(!AttachMultimodalSets(&ts, 0.9, dir.path().string(), "small"));  // other threshold
  CHECK(ts.multimodal.set_size(0) == 2);                                 // {0, 1}
  // Another clip changes the last poses: a fresh computation, not the stale file.
  const Clip b2 = StillClip("b", "bow", 7, 5.0f, 0.1f, 0);
  TestSet ts2 = BuildTestSet({&a, &b2}, SmallProtocol());
  CHECK(!AttachMultimodalSets(&ts2, 0.5, dir.path().string(), "small"));
  CHECK(SetOf(ts2.multimodal, 0) == std::vector<int>{0, 2});

  // Round trip and corruption of the file itself.
  const std::string path = dir.file("sets.bin");
  WriteMultimodalCache(path, 42, first);
  MultimodalSets back;
  CHECK(ReadMultimodalCache(path, 42, &back));
  CHECK(back.members == first.members);
  CHECK(!ReadMultimodalCache(path, 43, &back));
  CHECK(!ReadMultimodalCache(dir.file("missing.bin"), 42, &back));
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), bytes.size() - 2);
  }
  CHECK_THROWS_AS(ReadMultimodalCache(path, 42, &back), FormatError);
  CHECK_THROWS_WITH(ReadMultimodalCache(path, 42, &back), Catch::Contains("truncated"));
}
