// DihedralBending (constraints_bending.hpp): angle against geometric
// references, analytic gradient against central finite differences at 50
// random hinges (including flat and fully folded ones, where the seed's
// arccos form has an infinite gradient), compile() validation, and finite
// results on degenerate hinges.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;
constexpr Real kPi = std::numbers::pi_v<Real>;

// Central differences with step h = eps^(1/3): truncation h^2/6 |C'''| plus
// round-off ~ (a few eps)/h, both ~ eps^(2/3). The random hinges below have
// edge and heights >= 0.3 in a box of side 2, so |C'''| <= ~6/0.3^3 ~ 220 and
// the error is below ~40 eps^(2/3) per unit of gradient; the tolerance is
// 256 eps^(2/3) relative to max(1, max|g_i|): 9.4e-9 in double, 6.2e-3 in
// float. A wrong sign, particle or factor is an O(1) error.
const Real kFdStep = std::cbrt(kEps);
const Real kFdTol = Real(256) * std::cbrt(kEps) * std::cbrt(kEps);

::testing::AssertionResult gradient_matches_fd(const DihedralBending& c, std::vector<Vec3> x) {
  EvalContext ctx;
  ctx.x = x.data();
  Real C;
  Vec3 g[4];
  if (!DihedralBending::eval(c, 0, ctx, C, g)) return ::testing::AssertionFailure() << "eval refused";
  Real gmax = 1;
  for (const Vec3& gi : g) gmax = std::max(gmax, gi.norm());
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j) {
      const Real x0 = x[c.p[i]][j];
      const Real xp = x0 + kFdStep, xm = x0 - kFdStep;
      Real cp, cm;
      Vec3 unused[4];
      x[c.p[i]][j] = xp;
      const bool okp = DihedralBending::eval(c, 0, ctx, cp, unused);
      x[c.p[i]][j] = xm;
      const bool okm = DihedralBending::eval(c, 0, ctx, cm, unused);
      x[c.p[i]][j] = x0;
      if (!okp || !okm) return ::testing::AssertionFailure() << "eval refused near the point";
      // C is wrapped into (-pi, pi]; unwrap the difference.
      const Real fd = detail::wrap_angle(cp - cm) / (xp - xm);
      if (!(std::abs(fd - g[i][j]) <= kFdTol * gmax))
        return ::testing::AssertionFailure()
               << "particle " << i << " coord " << j << ": analytic " << g[i][j] << ", FD " << fd
               << ", C " << C;
    }
  return ::testing::AssertionSuccess();
}

// Hinge with edge along x from the origin, wing 2 in the xy plane (n1 = +z)
// and wing 3 rotated by `theta` about the edge from the flat position.
std::vector<Vec3> hinge(Real theta, Real a2 = Real(0.3), Real a3 = Real(0.6), Real h2 = 1,
                        Real h3 = Real(0.8)) {
  return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(a2, h2, 0),
          Vec3(a3, -h3 * std::cos(theta), h3 * std::sin(theta))};
}

TEST(DihedralBending, AngleMatchesConstruction) {
  // Rotating wing 3 towards +n1 by theta folds the hinge: phi = -theta
  // (sign convention documented in constraints_bending.hpp). Checked for
  // theta in (-pi, pi], with 0 (flat) and pi (fully folded) included.
  for (Real theta : {Real(0), Real(0.1), Real(1), Real(2), Real(3), Real(-0.5), Real(-3)}) {
    const auto x = hinge(theta);
    Real phi;
    ASSERT_TRUE(DihedralBending::angle({0, 1, 2, 3}, x.data(), phi));
    EXPECT_NEAR(phi, -theta, 16 * kEps) << "theta " << theta;
  }
  Real phi;
  const auto folded = hinge(kPi);
  ASSERT_TRUE(DihedralBending::angle({0, 1, 2, 3}, folded.data(), phi));
  EXPECT_NEAR(std::abs(phi), kPi, 16 * kEps);
}

TEST(DihedralBending, ValueIsWrappedDifference) {
  // rest 3 rad, current -3 rad: the short way round is 2 pi - 6 = 0.283 rad.
  const auto x = hinge(3);  // phi = -3
  EvalContext ctx;
  ctx.x = x.data();
  Real C;
  Vec3 g[4];
  ASSERT_TRUE(DihedralBending::eval(DihedralBending{{0, 1, 2, 3}, 3, {}}, 0, ctx, C, g));
  EXPECT_NEAR(C, 2 * kPi - 6, 64 * kEps);
}

TEST(DihedralBending, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<Real> u(-1, 1);
  const DihedralBending c{{0, 1, 2, 3}, Real(0.4), {}};
  int tested = 0;
  while (tested < 50) {
    std::vector<Vec3> x(4);
    for (auto& p : x) p = Vec3(u(rng), u(rng), u(rng));
    // Keep the hinge well conditioned (see kFdTol) and away from the wrap.
    const Vec3 e = x[1] - x[0];
    const Real l = e.norm();
    if (l < Real(0.3)) continue;
    if (e.cross(x[2] - x[0]).norm() / l < Real(0.3) || e.cross(x[3] - x[0]).norm() / l < Real(0.3))
      continue;
    Real phi;
    ASSERT_TRUE(DihedralBending::angle(c.p, x.data(), phi));
    if (std::abs(phi - c.rest_angle) > kPi - Real(0.3) && std::abs(phi - c.rest_angle) < kPi + Real(0.3))
      continue;
    EXPECT_TRUE(gradient_matches_fd(c, x)) << "config " << tested;
    ++tested;
  }
}

TEST(DihedralBending, GradientBoundedAtFlatAndFolded) {
  // At phi = 0 and phi = pi the arccos form's gradient is infinite; here each
  // wing's gradient has magnitude 1/height (1/1 and 1/0.8), and FD agrees
  // (rest = pi for the folded case so that C is smooth there).
  for (Real theta : {Real(0), kPi}) {
    const auto x = hinge(theta);
    const DihedralBending c{{0, 1, 2, 3}, theta, {}};
    EvalContext ctx;
    ctx.x = x.data();
    Real C;
    Vec3 g[4];
    ASSERT_TRUE(DihedralBending::eval(c, 0, ctx, C, g));
    EXPECT_NEAR(g[2].norm(), Real(1) / Real(1), 16 * kEps);
    EXPECT_NEAR(g[3].norm(), Real(1) / Real(0.8), 16 * kEps);
    EXPECT_TRUE(gradient_matches_fd(c, x)) << "theta " << theta;
  }
}

TEST(DihedralBending, DegenerateHingesAreSkipped) {
  EvalContext ctx;
  Real C;
  Vec3 g[4];
  const DihedralBending c{{0, 1, 2, 3}, 0, {}};
  // Zero-length hinge edge; wing on the hinge line (zero-area triangle);
  // all particles coincident.
  const std::vector<std::vector<Vec3>> cases = {
      {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0)},
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0.5, -1, 0)},
      {Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)}};
  for (const auto& x : cases) {
    ctx.x = x.data();
    EXPECT_FALSE(DihedralBending::eval(c, 0, ctx, C, g));
  }
}

SceneDesc hinge_scene(Real theta) {
  SceneDesc s;
  for (const Vec3& p : hinge(theta)) s.add_particle(p, 1);
  s.dihedral_bends.push_back(DihedralBendingDesc{{0, 1, 2, 3}, std::nullopt, {}});
  return s;
}

TEST(DihedralBending, CompileMeasuresRestAngle) {
  const Model m = compile(hinge_scene(Real(0.7)));
  ASSERT_EQ(m.get<DihedralBending>().size(), 1u);
  EXPECT_NEAR(m.get<DihedralBending>()[0].rest_angle, Real(-0.7), 16 * kEps);
}

TEST(DihedralBending, CompileRejectsBadInput) {
  auto s = hinge_scene(0);
  s.dihedral_bends[0].p[2] = 99;
  EXPECT_TRUE(test::scene_error_names(s, {"dihedral_bends[0]", "p2", "99", "[0, 4)"}));
  s = hinge_scene(0);
  s.dihedral_bends[0].p[3] = 1;
  EXPECT_TRUE(test::scene_error_names(s, {"dihedral_bends[0]", "p3", "duplicate particle 1", "p1"}));
  s = hinge_scene(0);
  s.dihedral_bends[0].rest_angle = Real(4);
  EXPECT_TRUE(test::scene_error_names(s, {"dihedral_bends[0]", "rest_angle", "4"}));
  s.dihedral_bends[0].rest_angle = std::nan("");
  EXPECT_TRUE(test::scene_error_names(s, {"dihedral_bends[0]", "rest_angle", "nan"}));
  s = hinge_scene(0);
  s.positions[2] = Vec3(3, 0, 0);  // wing on the hinge line
  EXPECT_TRUE(test::scene_error_names(s, {"dihedral_bends[0]", "degenerate"}));
  s = hinge_scene(0);
  s.dihedral_bends[0].mat.compliance = -1;
  EXPECT_TRUE(test::scene_error_names(s, {"dihedral_bends[0]", "mat.compliance", "-1"}));
}

// Steps a hinge whose positions are overwritten with a degenerate
// configuration; positions and multipliers must stay finite.
void expect_finite_after_steps(std::vector<Vec3> x, Real rest, Real compliance, Method method) {
  auto s = hinge_scene(Real(0.5));
  s.dihedral_bends[0].rest_angle = rest;
  s.dihedral_bends[0].mat.compliance = compliance;
  const Model m = compile(s);
  State st = make_state(m);
  st.x = x;
  StepConfig cfg;
  cfg.method = method;
  cfg.iterations = 4;
  for (int i = 0; i < 10; ++i) step(m, st, cfg);
  EXPECT_TRUE(test::all_finite(st)) << "rest " << rest << " compliance " << compliance;
}

TEST(DihedralBending, DegenerateConfigurationsStayFinite) {
  const std::vector<std::vector<Vec3>> cases = {
      std::vector<Vec3>(4, Vec3(1, 2, 3)),                                      // coincident
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 0), Vec3(0.5, -1, 0)},        // zero area
      {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, -1, 0)},        // zero edge
      hinge(0),                                                                 // flat
      hinge(kPi),                                                               // folded
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, 1, 0)}};        // wings coincide
  for (const auto& x : cases)
    for (Real rest : {Real(0), Real(1), kPi})
      for (Real alpha : {Real(0), Real(1e-3)})
        for (Method method : {Method::xpbd, Method::pbd}) expect_finite_after_steps(x, rest, alpha, method);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
