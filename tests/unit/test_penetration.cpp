// Penetration (constraints_contact.hpp): value against a hand-computed
// configuration, side recording, analytic gradient against central finite
// differences at 50 random configurations on both sides, compile()
// validation, finite results on degenerate configurations.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

// Central differences, h = eps^(1/3): error ~ h^2/6 |C'''| + (a few eps)/h,
// both ~ eps^(2/3). The random triangles keep edges and heights >= 0.3 and
// |q - x1| <= 2 sqrt(3), so each derivative of n brings a factor of at most
// ~1/0.3 and C''' is bounded by ~|d|/0.3^3 ~ 130 (the error stays below ~30
// eps^(2/3) per unit of gradient). Tolerance 256 eps^(2/3) relative to
// max(1, max|g|): 9.4e-9 in double, 6.2e-3 in float; a float run with 32
// instead of 256 still passes, so the margin is > 8x.
const Real kFdStep = std::cbrt(kEps);
const Real kFdTol = Real(256) * std::cbrt(kEps) * std::cbrt(kEps);

TEST(Penetration, ValueAndSide) {
  // Triangle in z = 0, counter-clockwise seen from +z: n = +z.
  const std::vector<Vec3> x = {Vec3(0.2, 0.3, 0.5), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const Penetration c{{0, 1, 2, 3}, Real(0.1), {}};
  EXPECT_EQ(Penetration::side(c, x.data()), Real(1));
  Real side = 1;
  EvalContext ctx;
  ctx.x = x.data();
  ctx.penetration_side = &side;
  Real C;
  Vec3 g[4];
  ASSERT_TRUE(Penetration::eval(c, 0, ctx, C, g));
  EXPECT_NEAR(C, Real(0.4), 4 * kEps);
  EXPECT_TRUE(g[0].isApprox(Vec3::UnitZ(), 4 * kEps));
  // Same position judged from the other side: C = -0.5 - 0.1.
  side = -1;
  ASSERT_TRUE(Penetration::eval(c, 0, ctx, C, g));
  EXPECT_NEAR(C, Real(-0.6), 4 * kEps);
  EXPECT_TRUE(g[0].isApprox(-Vec3::UnitZ(), 4 * kEps));
  // Below the plane, and exactly in it (documented: counts as +1).
  std::vector<Vec3> below = x;
  below[0].z() = Real(-0.5);
  EXPECT_EQ(Penetration::side(c, below.data()), Real(-1));
  below[0].z() = 0;
  EXPECT_EQ(Penetration::side(c, below.data()), Real(1));
}

TEST(Penetration, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Penetration c{{0, 1, 2, 3}, Real(0.05), {}};
  int tested = 0;
  while (tested < 50) {
    std::vector<Vec3> x(4);
    for (auto& p : x) p = Vec3(u(rng), u(rng), u(rng));
    const Vec3 e1 = x[2] - x[1], e2 = x[3] - x[1], e3 = x[3] - x[2];
    if (e1.norm() < Real(0.3) || e2.norm() < Real(0.3) || e3.norm() < Real(0.3)) continue;
    const Real area2 = e1.cross(e2).norm();
    if (area2 / e1.norm() < Real(0.3) || area2 / e2.norm() < Real(0.3) || area2 / e3.norm() < Real(0.3))
      continue;
    Real side = Penetration::side(c, x.data());
    EvalContext ctx;
    ctx.x = x.data();
    ctx.penetration_side = &side;
    Real C;
    Vec3 g[4];
    ASSERT_TRUE(Penetration::eval(c, 0, ctx, C, g));
    Real gmax = 1;
    for (const Vec3& gi : g) gmax = std::max(gmax, gi.norm());
    // Translation invariance: the gradients sum to zero.
    EXPECT_LE((g[0] + g[1] + g[2] + g[3]).norm(), 16 * kEps * gmax);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 3; ++j) {
        const Real x0 = x[i][j], xp = x0 + kFdStep, xm = x0 - kFdStep;
        Real cp, cm;
        Vec3 unused[4];
        x[i][j] = xp;
        ASSERT_TRUE(Penetration::eval(c, 0, ctx, cp, unused));
        x[i][j] = xm;
        ASSERT_TRUE(Penetration::eval(c, 0, ctx, cm, unused));
        x[i][j] = x0;
        EXPECT_NEAR((cp - cm) / (xp - xm), g[i][j], kFdTol * gmax)
            << "config " << tested << " side " << side << " particle " << i << " coord " << j;
      }
    ++tested;
  }
}

TEST(Penetration, ZeroAreaTriangleIsSkipped) {
  Real side = 1;
  EvalContext ctx;
  ctx.penetration_side = &side;
  Real C;
  Vec3 g[4];
  const Penetration c{{0, 1, 2, 3}, 0, {}};
  const std::vector<std::vector<Vec3>> cases = {
      {Vec3(0, 0, 1), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)},  // collinear
      {Vec3(0, 0, 1), Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0)},  // repeated vertex
      std::vector<Vec3>(4, Vec3(1, 1, 1))};                          // all coincident
  for (const auto& x : cases) {
    ctx.x = x.data();
    EXPECT_FALSE(Penetration::eval(c, 0, ctx, C, g));
  }
}

SceneDesc scene() {
  SceneDesc s;
  s.add_particle(Vec3(0.2, 0.2, 1), 1, Real(0.05));
  s.add_particle(Vec3(0, 0, 0), 0);
  s.add_particle(Vec3(1, 0, 0), 0);
  s.add_particle(Vec3(0, 1, 0), 0);
  s.penetrations.push_back(PenetrationDesc{{0, 1, 2, 3}, std::nullopt, {}});
  return s;
}

TEST(Penetration, CompileDefaultsThicknessToRadius) {
  const Model m = compile(scene());
  ASSERT_EQ(m.get<Penetration>().size(), 1u);
  EXPECT_EQ(m.get<Penetration>()[0].thickness, Real(0.05));
  const State st = make_state(m);
  ASSERT_EQ(st.penetration_side.size(), 1u);
  EXPECT_EQ(st.penetration_side[0], Real(1));
}

TEST(Penetration, CompileRejectsBadInput) {
  auto s = scene();
  s.penetrations[0].p[3] = 99;
  EXPECT_TRUE(test::scene_error_names(s, {"penetrations[0]", "p3", "99", "[0, 4)"}));
  s = scene();
  s.penetrations[0].p[1] = 0;
  EXPECT_TRUE(test::scene_error_names(s, {"penetrations[0]", "p1", "duplicate particle 0", "p0"}));
  s = scene();
  s.penetrations[0].thickness = Real(-0.1);
  EXPECT_TRUE(test::scene_error_names(s, {"penetrations[0]", "thickness", "-0.1"}));
  s = scene();
  s.positions[3] = Vec3(2, 0, 0);
  EXPECT_TRUE(test::scene_error_names(s, {"penetrations[0]", "zero area"}));
  s = scene();
  s.penetrations[0].mat.damping = -2;
  EXPECT_TRUE(test::scene_error_names(s, {"penetrations[0]", "mat.damping", "-2"}));
}

TEST(Penetration, StepRejectsMismatchedSideArray) {
  const Model m = compile(scene());
  State st = make_state(m);
  st.penetration_side.clear();
  EXPECT_TRUE(test::config_error_names(m, st, {}, {"penetration_side", "0", "1"}));
}

TEST(Penetration, DegenerateConfigurationsStayFinite) {
  // The triangle is movable here (mass 1) so that degenerate triangles also
  // receive corrections.
  const std::vector<std::vector<Vec3>> cases = {
      std::vector<Vec3>(4, Vec3(1, 2, 3)),                            // coincident
      {Vec3(0.5, 0, 1), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)},  // zero area
      {Vec3(0.2, 0.2, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)},  // q in the plane
      {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}};   // q on a vertex
  for (const auto& x : cases)
    for (Real alpha : {Real(0), Real(1e-4)})
      for (Method method : {Method::xpbd, Method::pbd}) {
        auto s = scene();
        for (int i = 1; i < 4; ++i) s.masses[i] = 1;
        s.penetrations[0].mat.compliance = alpha;
        const Model m = compile(s);
        State st = make_state(m);
        st.x = x;
        StepConfig cfg;
        cfg.method = method;
        cfg.iterations = 4;
        for (int i = 0; i < 10; ++i) step(m, st, cfg);
        EXPECT_TRUE(test::all_finite(st));
      }
}

TEST(Penetration, PointInPlaneIsPushedToNormalSide) {
  // A point exactly in the plane at the start of the step counts as on the
  // +n side and ends at the thickness on that side (kinematic triangle, no
  // gravity, one substep: C = 0 after the projection up to round-off; later
  // substeps would carry on with the velocity the correction produced).
  auto s = scene();
  s.positions[0] = Vec3(0.2, 0.2, 0);
  const Model m = compile(s);
  State st = make_state(m);
  StepConfig cfg;
  cfg.gravity = Vec3::Zero();
  cfg.substeps = 1;
  step(m, st, cfg);
  EXPECT_NEAR(st.x[0].z(), Real(0.05), 16 * kEps);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
