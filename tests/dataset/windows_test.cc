#include "dataset/windows.h"

#include <catch2/catch.hpp>
#include <map>

using namespace motionfork;

TEST_CASE("sliding windows follow DLow's rule or include the last start") {
  // DLow: range(0, T - L, stride)
  for (int T : {74, 75, 76, 89, 90, 91, 200}) {
    int dlow = 0;
    for (int i = 0; i < T - 75; i += 15) ++dlow;
    CHECK(CountSlidingWindows(T, 75, 15, false) == dlow);
    int incl = 0;
    for (int i = 0; i <= T - 75; i += 15) ++incl;
    CHECK(CountSlidingWindows(T, 75, 15, true) == incl);
  }
  const auto w = SlidingWindows({90, 10, 105}, 75, 15, true);
  REQUIRE(w.size() == 5);  // clip 0: starts 0, 15; clip 1: none; clip 2: 0, 15, 30
  CHECK(w[0].clip == 0);
  CHECK(w[1].start == 15);
  CHECK(w[2].clip == 2);
  CHECK(w[4].start == 30);
  CHECK_THROWS(CountSlidingWindows(10, 0, 1, true));
}

TEST_CASE("random windows are uniform over valid starts and reproducible") {
  RandomWindowSampler a({80, 75, 10}, 75, 42), b({80, 75, 10}, 75, 42);
  CHECK(a.num_candidates() == 7);  // 6 starts in clip 0, 1 in clip 1
  std::map<std::pair<int, int>, int> counts;
  for (int i = 0; i < 7000; ++i) {
    const Window wa = a.Next(), wb = b.Next();
    CHECK(wa.clip == wb.clip);
    CHECK(wa.start == wb.start);
    REQUIRE(wa.clip != 2);
    REQUIRE(wa.start + 75 <= (wa.clip == 0 ? 80 : 75));
    counts[{wa.clip, wa.start}]++;
  }
  CHECK(counts.size() == 7);
  for (const auto& [k, n] : counts) CHECK(n == Approx(1000).margin(150));
  CHECK_THROWS_WITH(RandomWindowSampler({10, 20}, 75, 1), Catch::Contains("75 frames"));
}
