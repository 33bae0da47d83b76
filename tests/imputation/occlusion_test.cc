// Occlusion masks, mask specs and AUROC.
#include "imputation/occlusion.h"

#include <catch2/catch.hpp>
#include <numeric>

#include "imputation/hgvae_experiments.h"
#include "io/npy.h"
#include "test_support.h"

using namespace motionfork;
using Catch::Contains;

TEST_CASE("occlusion: random shares are exact per window and reproducible") {
  for (double share : {0.01, 0.1, 0.5, 0.9}) {
    const auto m = RandomOcclusion(5, 720, share, 3);
    for (int w = 0; w < 5; ++w) {
      const int n = std::accumulate(m.begin() + w * 720, m.begin() + (w + 1) * 720, 0);
      CHECK(n == static_cast<int>(std::lround(share * 720)));
    }
    CHECK(m == RandomOcclusion(5, 720, share, 3));
    CHECK(m != RandomOcclusion(5, 720, share, 4));
  }
  // Never every value.
  const auto all = RandomOcclusion(1, 10, 1.0, 0);
  CHECK(std::accumulate(all.begin(), all.end(), 0) == 9);
}

TEST_CASE("occlusion: joints over windows, and the standard settings name whole limbs") {
  const auto skel = testing::MakeHumanoid();
  const auto m = JointOcclusion(2, 3, 17, {13});  // Hand_L
  for (size_t i = 0; i < m.size(); ++i) CHECK(m[i] == ((i % 48) / 3 == 12 ? 1 : 0));
  const std::vector<Occlusion> s = StandardOcclusions(*skel);
  REQUIRE(s.size() == 8);
  CHECK(s[4].name == "left arm");
  CHECK(s[4].joints == std::vector<int>{11, 12, 13});
  CHECK(s[6].name == "left leg");
  CHECK(s[6].joints == std::vector<int>{4, 5, 6});
}

TEST_CASE("occlusion: mask specs and their errors") {
  const auto skel = testing::MakeHumanoid();
  const auto m = MaskFromSpec("joints:Hand_L,Head@2-3", *skel, 6, 0);
  REQUIRE(m.size() == 6u * 51);
  int n = std::accumulate(m.begin(), m.end(), 0);
  CHECK(n == 2 * 2 * 3);
  CHECK(m[2 * 51 + 13 * 3] == 1);
  CHECK(m[1 * 51 + 13 * 3] == 0);
  const auto r = MaskFromSpec("random:0.5", *skel, 4, 1);
  CHECK(std::accumulate(r.begin(), r.end(), 0) == 96);
  for (int t = 0; t < 4; ++t)
    for (int a = 0; a < 3; ++a) CHECK(r[t * 51 + a] == 0);  // never the root
  CHECK_THROWS_WITH(MaskFromSpec("joints:Hand_X", *skel, 6, 0),
                    Contains("Hand_X") && Contains("Hand_L"));
  CHECK_THROWS_WITH(MaskFromSpec("joints:Hips", *skel, 6, 0), Contains("root"));
  CHECK_THROWS_WITH(MaskFromSpec("joints:Head@4-9", *skel, 6, 0), Contains("0..5"));
  CHECK_THROWS_WITH(MaskFromSpec("random:2", *skel, 6, 0), Contains("between 0 and 1"));
  CHECK_THROWS_WITH(MaskFromSpec("nose", *skel, 6, 0), Contains("expected random:SHARE"));
}

TEST_CASE("occlusion: a joints x frames mask file") {
  const auto skel = testing::MakeHumanoid();
  testing::TempDir dir;
  NpyArray a{{4, 17}, std::vector<float>(68, 0.0f)};
  a.data[2 * 17 + 13] = 1;  // frame 2, Hand_L
  WriteNpy(dir.file("m.npy"), a);
  const auto m = MaskFromSpec(dir.file("m.npy"), *skel, 4, 0);
  CHECK(std::accumulate(m.begin(), m.end(), 0) == 3);
  CHECK(m[2 * 51 + 39] == 1);
  CHECK_THROWS_WITH(MaskFromSpec(dir.file("m.npy"), *skel, 5, 0),
                    Contains("[5, 17]") && Contains("[4, 17]"));
  a.data[17] = 1;  // frame 1, the root
  WriteNpy(dir.file("root.npy"), a);
  CHECK_THROWS_WITH(MaskFromSpec(dir.file("root.npy"), *skel, 4, 0),
                    Contains("frame 1") && Contains("root"));
}

TEST_CASE("auroc: perfect, reversed, ties and chance") {
  CHECK(Auroc({3, 4, 5}, {0, 1, 2}) == 1.0);
  CHECK(Auroc({0, 1}, {3, 4}) == 0.0);
  CHECK(Auroc({1, 1}, {1, 1}) == 0.5);
  CHECK(Auroc({1, 3}, {2}) == 0.5);
  CHECK_THROWS_AS(Auroc({}, {1}), std::invalid_argument);
}
