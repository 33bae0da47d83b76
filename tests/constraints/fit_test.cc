// Range fitting: percentiles, pooling of the two sides, margin and rounding, writing back.
#include "constraints/fit.h"

#include <catch2/catch.hpp>
#include <fstream>

#include "config/constraint_config.h"
#include "fixtures.h"
#include "io/file_util.h"
#include "test_support.h"

using namespace motionfork;
using namespace motionfork::testing;

namespace {

// The h36m set's knee angle alone, its range removed (to be fitted).
ConstraintSetSpec KneeOnly() {
  ConstraintSetSpec spec = ShippedConstraints("h36m");
  spec.constraints.erase(
      std::remove_if(spec.constraints.begin(), spec.constraints.end(),
                     [](const ConstraintSpec& c) { return c.name != "Leg2ThighPlane"; }),
      spec.constraints.end());
  spec.constraints[0].has_range = false;
  return spec;
}

ConstraintBuildOptions WithoutRanges() {
  ConstraintBuildOptions o;
  o.require_ranges = false;
  return o;
}

}  // namespace

TEST_CASE("percentiles interpolate linearly between order statistics (NumPy's default)") {
  std::vector<float> v;
  for (int i = 100; i >= 0; --i) v.push_back(static_cast<float>(i));  // 0..100, reversed
  CHECK(Percentile(&v, 0) == 0);
  CHECK(Percentile(&v, 100) == 100);
  CHECK(Percentile(&v, 50) == 50);
  CHECK(Percentile(&v, 0.1) == Approx(0.1));
  CHECK(Percentile(&v, 99.9) == Approx(99.9));
  std::vector<float> two = {10, 20};
  CHECK(Percentile(&two, 25) == Approx(12.5));
  std::vector<float> one = {7};
  CHECK(Percentile(&one, 99.9) == 7);
  std::vector<float> none;
  CHECK_THROWS_AS(Percentile(&none, 50), std::invalid_argument);
}

TEST_CASE("fitting pools both sides, adds the margin, rounds outwards and writes valid YAML") {
  // One per-side constraint: the knee angle, swept over different ranges on the two sides.
  const auto s = ShippedSkeleton("h36m").skeleton;
  const Pose neutral = H36mNeutral(*s);
  const BodyAxes ax = Axes(*s, neutral, "LHip", "RHip", "Hips", "Thorax");
  ConstraintSetSpec spec = KneeOnly();
  const ConstraintBuildOptions no_ranges = WithoutRanges();
  const ConstraintSet set = ConstraintSet::Build(spec, *s, no_ranges);
  const float rest = CheckPose(set, neutral).angles[0];  // ~96 degrees

  std::vector<float> frames;
  for (int i = 0; i <= 1000; ++i) {
    Pose p = neutral;
    // Left knee flexed 0..50 degrees, right knee 0..20: pooled 2002 angles.
    Rotate(*s, &p, {"LFoot"}, At(*s, p, "LKnee"), ax.left, 50.0f * i / 1000);
    Rotate(*s, &p, {"RFoot"}, At(*s, p, "RKnee"), ax.left, 20.0f * i / 1000);
    frames.insert(frames.end(), p.begin(), p.end());
  }
  FitOptions o;
  o.low_percentile = 0;
  o.high_percentile = 100;
  o.margin_deg = 1.5;
  o.round_deg = 0.5;
  RangeFitter fitter(set, o);
  fitter.Add(frames.data(), 1001);
  CHECK(fitter.frames() == 1001);
  const std::vector<FittedRange> ranges = fitter.Fit();
  REQUIRE(ranges.size() == 1);
  CHECK(ranges[0].name == "Leg2ThighPlane");
  CHECK(ranges[0].samples == 2002);
  CHECK(ranges[0].degenerate == 0);
  CHECK(ranges[0].low_value_deg == Approx(rest).margin(0.01));
  CHECK(ranges[0].high_value_deg == Approx(rest + 50).margin(0.01));
  CHECK(ranges[0].lower_deg == Approx(std::floor((rest - 1.5) * 2) / 2).margin(1e-9));
  CHECK(ranges[0].upper_deg == Approx(std::ceil((rest + 51.5) * 2) / 2).margin(1e-9));

  // The median of the pooled sides lies between the two sides' own medians.
  o.low_percentile = 50;
  o.high_percentile = 75;
  o.margin_deg = 0;
  o.round_deg = 0;
  RangeFitter pooled(set, o);
  pooled.Add(frames.data(), 1001);
  const FittedRange mid = pooled.Fit()[0];
  CHECK(mid.low_value_deg > rest + 10.5);
  CHECK(mid.low_value_deg < rest + 25.5);

  // Written back: the same definitions, the fitted range, a header; and it loads again.
  const ConstraintSetSpec fitted = WithFittedRanges(spec, ranges);
  const std::string text = FormatConstraintConfig(fitted, "fitted by a test");
  TempDir dir;
  WriteFileAtomically(dir.file("fitted.yaml"), text);
  const ConstraintSetSpec back = LoadConstraintConfig(dir.file("fitted.yaml"));
  REQUIRE(back.constraints.size() == 1);
  CHECK(back.constraints[0].lower_deg == ranges[0].lower_deg);
  CHECK(back.constraints[0].upper_deg == ranges[0].upper_deg);
  CHECK(back.constraints[0].a_text == spec.constraints[0].a_text);
  CHECK(text.find("# fitted: 2002 angles") != std::string::npos);
  const ConstraintSet bound = ConstraintSet::Build(back, *s);
  // Every training frame is inside the fitted range.
  std::vector<AngleStatus> st(2002);
  AngleChecker(bound).Run(frames.data(), 1001, nullptr, st.data());
  for (AngleStatus x : st) CHECK(x == AngleStatus::kInside);
}

TEST_CASE("fitting widens a range to its anatomical limit and merged fitters fit as one") {
  const auto s = ShippedSkeleton("h36m").skeleton;
  const Pose neutral = H36mNeutral(*s);
  const BodyAxes ax = Axes(*s, neutral, "LHip", "RHip", "Hips", "Thorax");
  ConstraintSetSpec spec = KneeOnly();
  const ConstraintBuildOptions no_ranges = WithoutRanges();
  const ConstraintSet set = ConstraintSet::Build(spec, *s, no_ranges);
  std::vector<float> first, second;
  for (int i = 0; i <= 100; ++i) {
    Pose p = neutral;
    Rotate(*s, &p, {"LFoot"}, At(*s, p, "LKnee"), ax.left, 0.3f * i);
    (i % 2 ? first : second).insert((i % 2 ? first : second).end(), p.begin(), p.end());
  }
  FitOptions o;
  o.round_deg = 0;
  RangeFitter a(set, o), b(set, o), both(set, o);
  a.Add(first.data(), 50);
  b.Add(second.data(), 51);
  both.Add(first.data(), 50);
  both.Add(second.data(), 51);
  a.Merge(b);
  CHECK(a.frames() == 101);
  const FittedRange merged = a.Fit()[0], whole = both.Fit()[0];
  CHECK(merged.samples == whole.samples);
  CHECK(merged.lower_deg == whole.lower_deg);
  CHECK(merged.upper_deg == whole.upper_deg);
  CHECK_FALSE(whole.widened);
  CHECK(whole.upper_deg < 160);  // knees bent at most 30 degrees from ~96

  // A literature limit beyond the data's range widens it, on the side it reaches past.
  spec.constraints[0].has_anatomical = true;
  spec.constraints[0].anatomical_lower_deg = 80;
  spec.constraints[0].anatomical_upper_deg = 180;
  const ConstraintSet limited = ConstraintSet::Build(spec, *s, no_ranges);
  RangeFitter c(limited, o);
  c.Add(first.data(), 50);
  const std::vector<FittedRange> ranges = c.Fit();
  CHECK(ranges[0].widened);
  CHECK(ranges[0].lower_deg == 80);
  CHECK(ranges[0].upper_deg == 180);
  const ConstraintSetSpec fitted = WithFittedRanges(spec, ranges);
  const std::string text = FormatConstraintConfig(fitted, "fitted by a test");
  CHECK(text.find("widened to the anatomical limit") != std::string::npos);
  CHECK(text.find("anatomical: [80, 180]") != std::string::npos);
  TempDir dir;
  WriteFileAtomically(dir.file("fitted.yaml"), text);
  const ConstraintSetSpec back = LoadConstraintConfig(dir.file("fitted.yaml"));
  CHECK(back.constraints[0].has_anatomical);
  CHECK(back.constraints[0].anatomical_lower_deg == 80);
  CHECK(back.constraints[0].anatomical_upper_deg == 180);

  // A limit inside the data's range changes nothing.
  spec.constraints[0].anatomical_lower_deg = 100;
  spec.constraints[0].anatomical_upper_deg = 110;
  const ConstraintSet inner = ConstraintSet::Build(spec, *s, no_ranges);
  RangeFitter d(inner, o);
  d.Add(first.data(), 50);
  CHECK_FALSE(d.Fit()[0].widened);
}

TEST_CASE("fitting: options are validated, degenerate angles skipped, empty data refused") {
  const auto s = ShippedSkeleton("h36m").skeleton;
  ConstraintBuildOptions no_ranges;
  no_ranges.require_ranges = false;
  const ConstraintSet set = ConstraintSet::Build(ShippedConstraints("h36m"), *s, no_ranges);
  FitOptions bad;
  bad.low_percentile = 60;
  bad.high_percentile = 40;
  CHECK_THROWS_WITH(RangeFitter(set, bad),
                    Catch::Contains("high_percentile") && Catch::Contains("40"));
  bad = FitOptions{};
  bad.margin_deg = -1;
  CHECK_THROWS_WITH(RangeFitter(set, bad), Catch::Contains("margin_deg"));

  RangeFitter empty(set);
  CHECK_THROWS_WITH(empty.Fit(),
                    Catch::Contains("Neck2Spine") && Catch::Contains("no defined angle"));

  // A frame with a zero-length thigh: its thigh angles are skipped and counted.
  Pose p = H36mNeutral(*s);
  const Pose ok = p;
  const int knee = s->Index("LKnee"), hip = s->Index("LHip");
  for (int a = 0; a < 3; ++a) p[3 * knee + a] = p[3 * hip + a];
  std::vector<float> frames = ok;
  frames.insert(frames.end(), p.begin(), p.end());
  RangeFitter fitter(set);
  fitter.Add(Motion(s, 50, frames));
  for (const FittedRange& r : fitter.Fit()) {
    INFO(r.name);
    const bool thigh = r.name == "Leg2ThighPlane" || r.name == "Thigh2TorsoPlane";
    CHECK(r.degenerate == (thigh ? 1 : 0));
    CHECK(r.lower_deg >= 0);
    CHECK(r.upper_deg <= 180);
    CHECK(r.lower_deg <= r.upper_deg);
  }
  CHECK_THROWS_AS(
      fitter.Add(Motion(ShippedSkeleton("humaneva").skeleton, 60, std::vector<float>(45, 0.0f))),
      std::invalid_argument);
}
