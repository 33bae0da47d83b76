// The LibTorch penalty: agreement with the checker, values, gradients, degenerate input, shapes.
// LibTorch first: it brings glog, whose CHECK would silently replace Catch's (failed checks would
// abort instead of being reported); drop glog's, then include Catch.
#include <torch/torch.h>
#undef CHECK
#include <catch2/catch.hpp>
#include <cmath>

#include "constraints/torch/angle_penalty.h"
#include "fixtures.h"
#include "test_support.h"

using namespace motionfork;
using namespace motionfork::testing;

namespace {

torch::Tensor ToTensor(const std::vector<float>& poses, int n, int joints) {
  return torch::from_blob(const_cast<float*>(poses.data()), {n, joints, 3}, torch::kFloat).clone();
}

struct Agreement {
  long long compared = 0, violated = 0, penalised = 0, near_bound = 0, degenerate = 0;
  long long mismatches = 0;
};

// Checker statuses vs penalty > 0 on n poses. With applied-bound masks, a violation counts as
// penalised only when the crossed bound is applied.
Agreement Compare(const ConstraintSet& set, const std::vector<float>& poses, int n,
                  const AnglePenaltyOptions& options) {
  const int C = set.num_constraints();
  std::vector<float> angles(static_cast<size_t>(n) * C);
  std::vector<AngleStatus> status(angles.size());
  AngleChecker(set, options.degeneracy).Run(poses.data(), n, angles.data(), status.data());
  AnglePenalty penalty(set, options);
  const torch::Tensor per = penalty->PerConstraint(ToTensor(poses, n, set.num_joints()));
  REQUIRE(per.sizes() == torch::IntArrayRef({n, C}));
  const auto p = per.accessor<float, 2>();
  const torch::Tensor lower_on = penalty->lower_applied(), upper_on = penalty->upper_applied();
  Agreement a;
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < C; ++c) {
      const Constraint& k = set.constraint(c);
      const float angle = angles[static_cast<size_t>(i) * C + c];
      const AngleStatus s = status[static_cast<size_t>(i) * C + c];
      REQUIRE(std::isfinite(p[i][c]));
      if (s == AngleStatus::kDegenerate) {
        ++a.degenerate;
        CHECK(p[i][c] == 0.0f);
        continue;
      }
      // Float angles and float cosines may disagree within a hair of a bound.
      if (std::abs(angle - k.lower_deg) < 0.01 || std::abs(angle - k.upper_deg) < 0.01) {
        ++a.near_bound;
        continue;
      }
      ++a.compared;
      const bool expected = (s == AngleStatus::kBelow && lower_on[c].item<bool>()) ||
                            (s == AngleStatus::kAbove && upper_on[c].item<bool>());
      a.violated += IsViolation(s);
      a.penalised += p[i][c] > 0;
      if (expected != (p[i][c] > 0)) {
        ++a.mismatches;
        UNSCOPED_INFO(k.name << " angle " << angle << " status " << ToString(s) << " penalty "
                             << p[i][c]);
      }
    }
  }
  return a;
}

}  // namespace

TEST_CASE("checker and penalty agree on which constraints are violated (random poses)") {
  torch::set_num_threads(1);
  const auto h36m = ShippedSkeleton("h36m").skeleton;
  const auto humaneva = ShippedSkeleton("humaneva").skeleton;
  const auto bandai = ShippedSkeleton("bandai").skeleton;
  const int n = 4000;
  struct Run {
    std::string set;
    std::shared_ptr<const Skeleton> skeleton;
    Pose base;
  };
  for (const Run& r : {Run{"h36m", h36m, H36mNeutral(*h36m)},
                       Run{"humaneva", humaneva, HumanEvaNeutral(*humaneva)},
                       Run{"bandai", bandai, H36mNeutral(*h36m)}}) {
    const ConstraintSet set = ShippedSet(r.set, *r.skeleton);
    const std::vector<float> poses = RandomPoses(r.base, n, 0.15f, 17);
    for (const auto& [cos_limit, fused] :
         {std::make_pair(0.98, true), std::make_pair(1.0, true), std::make_pair(0.98, false),
          std::make_pair(1.0, false)}) {
      AnglePenaltyOptions o;
      o.cos_limit = cos_limit;
      o.fused_cpu = fused;
      const Agreement a = Compare(set, poses, n, o);
      INFO(r.set << (fused ? " fused" : " composed") << " cos_limit " << cos_limit << ": "
                 << a.compared << " compared, " << a.violated << " violated, " << a.penalised
                 << " penalised, " << a.near_bound << " within 0.01 deg of a bound, "
                 << a.degenerate << " degenerate");
      CHECK(a.mismatches == 0);
      CHECK(a.compared > 0.99 * n * set.num_constraints());
      CHECK(a.violated > 0.1 * a.compared);  // plenty of both outcomes
      CHECK(a.violated < 0.9 * a.compared);
      if (cos_limit == 1.0) CHECK(a.penalised == a.violated);
    }
  }
}

TEST_CASE("penalty: GSPS's cos-limit leaves bounds near 0 and 180 degrees unapplied") {
  torch::set_num_threads(1);
  ConstraintSetSpec spec;
  spec.name = "limits";
  ConstraintSpec c;
  c.name = "Knee";
  c.a = VectorExpr::Bone("LKnee", "LFoot");
  c.b = VectorExpr::Bone("LHip", "LKnee");
  c.has_range = true;
  c.lower_deg = 5;    // cos 0.996: not applied under 0.98
  c.upper_deg = 120;  // cos -0.5: applied
  spec.constraints = {c};
  const auto s = ShippedSkeleton("h36m").skeleton;
  const ConstraintSet set = ConstraintSet::Build(spec, *s);
  AnglePenalty penalty(set);
  CHECK_FALSE(penalty->lower_applied()[0].item<bool>());
  CHECK(penalty->upper_applied()[0].item<bool>());
  AnglePenaltyOptions all;
  all.cos_limit = 1.0;
  AnglePenalty strict(set, all);
  CHECK(strict->lower_applied()[0].item<bool>());
  CHECK(strict->upper_applied()[0].item<bool>());
  AnglePenaltyOptions bad;
  bad.cos_limit = 1.5;
  CHECK_THROWS_WITH(AnglePenalty(set, bad), Catch::Contains("cos_limit") && Catch::Contains("1.5"));
}

TEST_CASE("penalty: zero inside the range, squared cosine distance outside, exact gradients") {
  torch::set_num_threads(1);
  const bool fused = GENERATE(true, false);
  INFO((fused ? "fused CPU kernel" : "composed tensor ops"));
  const auto s = ShippedSkeleton("h36m").skeleton;
  const ConstraintSet set = ShippedSet("h36m", *s);
  AnglePenaltyOptions options;
  options.fused_cpu = fused;
  AnglePenalty penalty(set, options);
  penalty->to(torch::kDouble);
  const Pose neutral = H36mNeutral(*s);
  const BodyAxes ax = Axes(*s, neutral, "LHip", "RHip", "Hips", "Thorax");

  // Inside every range: zero penalty, zero gradient.
  torch::Tensor x = ToTensor(neutral, 1, 17).to(torch::kDouble).requires_grad_(true);
  torch::Tensor loss = penalty->forward(x);
  loss.backward();
  CHECK(loss.item<double>() == 0.0);
  CHECK(x.grad().abs().max().item<double>() == 0.0);

  // Knee bent backwards: (cos(angle) - cos(80 deg))^2 on Leg2ThighPlane_L only.
  Pose bent = neutral;
  Rotate(*s, &bent, {"LFoot"}, At(*s, bent, "LKnee"), ax.left, -50);
  const PoseCheck chk = CheckPose(set, bent);
  const int knee = set.Find("Leg2ThighPlane_L");
  const double angle = chk.angles[knee] * M_PI / 180.0;
  torch::Tensor y = ToTensor(bent, 1, 17).to(torch::kDouble).requires_grad_(true);
  const torch::Tensor per = penalty->PerConstraint(y);
  const double expected = std::pow(std::cos(angle) - std::cos(80 * M_PI / 180.0), 2);
  CHECK(per[0][knee].item<double>() == Approx(expected).epsilon(1e-4));
  CHECK(per.sum().item<double>() == Approx(expected).epsilon(1e-4));

  // Gradient against central finite differences (double precision).
  torch::Tensor total = penalty->forward(y);
  total.backward();
  const torch::Tensor g = y.grad().clone();
  CHECK(g.abs().max().item<double>() > 0);
  torch::NoGradGuard no_grad;
  const double h = 1e-6;
  double worst = 0;
  torch::Tensor base = y.detach().clone();
  for (int j = 0; j < 17; ++j) {
    for (int a = 0; a < 3; ++a) {
      torch::Tensor plus = base.clone(), minus = base.clone();
      plus[0][j][a] += h;
      minus[0][j][a] -= h;
      const double fd =
          (penalty->forward(plus).item<double>() - penalty->forward(minus).item<double>()) /
          (2 * h);
      worst = std::max(worst, std::abs(fd - g[0][j][a].item<double>()));
    }
  }
  CHECK(worst < 1e-6);
}

TEST_CASE("penalty: batches [B, T, J, 3], degenerate poses stay finite, shape errors") {
  torch::set_num_threads(1);
  const auto s = ShippedSkeleton("h36m").skeleton;
  const ConstraintSet set = ShippedSet("h36m", *s);
  AnglePenalty penalty(set);
  const std::vector<float> poses = RandomPoses(H36mNeutral(*s), 2 * 3, 0.15f, 23);
  const torch::Tensor flat = ToTensor(poses, 6, 17);
  const torch::Tensor batch = flat.reshape({2, 3, 17, 3});
  const torch::Tensor per = penalty->PerConstraint(batch);
  CHECK(per.sizes() == torch::IntArrayRef({2, 3, set.num_constraints()}));
  CHECK(torch::allclose(per.reshape({6, -1}), penalty->PerConstraint(flat)));
  CHECK(penalty->forward(batch).item<float>() == Approx(per.sum(-1).mean().item<float>()));

  // Every joint on one point, and a zero-length bone: no NaN in value or gradient.
  torch::Tensor collapsed = torch::full({1, 2, 17, 3}, 0.5f);
  collapsed[0][1] = ToTensor(H36mNeutral(*s), 1, 17)[0];
  collapsed[0][1][s->Index("LKnee")] = collapsed[0][1][s->Index("LHip")];
  collapsed.requires_grad_(true);
  torch::Tensor defined;
  const torch::Tensor cosines = penalty->Cosines(collapsed, &defined);
  CHECK_FALSE(defined[0][0].any().item<bool>());
  CHECK_FALSE(defined[0][1][set.Find("Leg2ThighPlane_L")].item<bool>());
  CHECK(defined[0][1][set.Find("Leg2ThighPlane_R")].item<bool>());
  const torch::Tensor loss = penalty->forward(collapsed) + cosines.sum();
  loss.backward();
  CHECK(std::isfinite(loss.item<float>()));
  CHECK(torch::isfinite(collapsed.grad()).all().item<bool>());

  CHECK_THROWS_WITH(penalty->forward(torch::zeros({4, 15, 3})),
                    Catch::Contains("[..., 17, 3]") && Catch::Contains("15"));
  CHECK_THROWS_WITH(penalty->forward(torch::zeros({4, 17, 3}, torch::kLong)),
                    Catch::Contains("floating-point"));
}

TEST_CASE(
    "penalty: the fused CPU kernel and composed tensor ops give the same values and gradients") {
  torch::set_num_threads(1);
  for (const std::string name : {"h36m", "humaneva", "bandai"}) {
    INFO(name);
    const auto s = ShippedSkeleton(name).skeleton;
    const ConstraintSet set = ShippedSet(name, *s);
    const Pose base =
        name == "humaneva" ? HumanEvaNeutral(*s) : H36mNeutral(*ShippedSkeleton("h36m").skeleton);
    const std::vector<float> poses = RandomPoses(base, 2000, 0.15f, 29);
    AnglePenalty fused(set);
    const torch::Tensor w = torch::rand({4, 500, set.num_constraints()}, torch::kDouble);
    for (auto dtype : {torch::kFloat, torch::kDouble}) {
      const torch::Tensor x0 =
          ToTensor(poses, 2000, s->num_joints()).reshape({4, 500, -1, 3}).to(dtype);
      torch::Tensor x1 = x0.clone().requires_grad_(true), x2 = x0.clone().requires_grad_(true);
      const torch::Tensor p1 = fused->PerConstraint(x1), p2 = fused->PerConstraintComposed(x2);
      REQUIRE(p1.sizes() == p2.sizes());
      const double tol = dtype == torch::kFloat ? 1e-5 : 1e-12;
      CHECK((p1 - p2).abs().max().item<double>() < tol);
      (p1 * w.to(dtype)).sum().backward();
      (p2 * w.to(dtype)).sum().backward();
      const double scale = x2.grad().abs().max().item<double>();
      CHECK(scale > 0);
      CHECK((x1.grad() - x2.grad()).abs().max().item<double>() <
            (dtype == torch::kFloat ? 1e-3 : 1e-9) * scale);
    }
  }
}
