// Tether (constraints_contact.hpp): value, gradient against central finite
// differences at 50 random configurations, compile() validation, finite
// results for coincident particles, and inequality behaviour (slack tether
// does nothing, taut tether pulls back to its length).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

TEST(Tether, GradientMatchesFiniteDifferences) {
  // C = L - |d|: |C'''| <= 3/|d|^2 <= 48 for |d| >= 0.25, so the central
  // difference error with h = eps^(1/3) is below (48/6 + a few) eps^(2/3);
  // tolerance 64 eps^(2/3): 2.4e-9 in double, 1.6e-3 in float.
  const Real h = std::cbrt(kEps);
  const Real tol = Real(64) * h * h;
  std::mt19937 rng(13);
  std::uniform_real_distribution<Real> u(-1, 1);
  const Tether c{{0, 1}, Real(0.7), {}};
  int tested = 0;
  while (tested < 50) {
    std::vector<Vec3> x = {Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng))};
    if ((x[0] - x[1]).norm() < Real(0.25)) continue;
    EvalContext ctx;
    ctx.x = x.data();
    Real C;
    Vec3 g[2];
    ASSERT_TRUE(Tether::eval(c, 0, ctx, C, g));
    EXPECT_NEAR(C, Real(0.7) - (x[0] - x[1]).norm(), 4 * kEps);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 3; ++j) {
        const Real x0 = x[i][j], xp = x0 + h, xm = x0 - h;
        Real cp, cm;
        Vec3 unused[2];
        x[i][j] = xp;
        ASSERT_TRUE(Tether::eval(c, 0, ctx, cp, unused));
        x[i][j] = xm;
        ASSERT_TRUE(Tether::eval(c, 0, ctx, cm, unused));
        x[i][j] = x0;
        EXPECT_NEAR((cp - cm) / (xp - xm), g[i][j], tol) << "config " << tested;
      }
    ++tested;
  }
}

TEST(Tether, CoincidentIsSkipped) {
  const std::vector<Vec3> x = {Vec3(1, 2, 3), Vec3(1, 2, 3)};
  EvalContext ctx;
  ctx.x = x.data();
  Real C;
  Vec3 g[2];
  EXPECT_FALSE(Tether::eval(Tether{{0, 1}, 1, {}}, 0, ctx, C, g));
}

SceneDesc scene(Real start_distance) {
  SceneDesc s;
  s.add_particle(Vec3(0, 0, 0), 0);  // kinematic anchor
  s.add_particle(Vec3(start_distance, 0, 0), 1);
  s.tethers.push_back(TetherDesc{1, 0, Real(1), {}});
  return s;
}

TEST(Tether, SlackDoesNothingTautPullsBack) {
  StepConfig cfg;
  cfg.gravity = Vec3::Zero();
  {
    // Inside the length: free motion (no constraint force), x = x0 + v t.
    auto s = scene(Real(0.5));
    s.velocities = {Vec3::Zero(), Vec3(Real(0.6), 0, 0)};
    const Model m = compile(s);
    State st = make_state(m);
    step(m, st, cfg);
    EXPECT_NEAR(st.x[1].x(), Real(0.5) + Real(0.6) * cfg.dt, 16 * kEps);
    EXPECT_EQ(st.lambdas<Tether>()[0], Real(0));
  }
  {
    // Beyond the length, moving outward: projected back onto the sphere.
    auto s = scene(Real(1.5));
    s.velocities = {Vec3::Zero(), Vec3(1, 0, 0)};
    const Model m = compile(s);
    State st = make_state(m);
    step(m, st, cfg);
    EXPECT_NEAR(st.x[1].norm(), Real(1), 16 * kEps);
  }
}

TEST(Tether, CompileRejectsBadInput) {
  auto s = scene(1);
  s.tethers[0].anchor = 5;
  EXPECT_TRUE(test::scene_error_names(s, {"tethers[0]", "anchor", "5", "[0, 2)"}));
  s = scene(1);
  s.tethers[0].anchor = 1;
  EXPECT_TRUE(test::scene_error_names(s, {"tethers[0]", "anchor", "duplicate particle 1"}));
  s = scene(1);
  s.tethers[0].length = Real(0);
  EXPECT_TRUE(test::scene_error_names(s, {"tethers[0]", "length", "0"}));
  s = scene(0);
  s.tethers[0].length.reset();  // initial distance 0
  EXPECT_TRUE(test::scene_error_names(s, {"tethers[0]", "length", "coincide"}));
  s = scene(Real(0.5));
  s.tethers[0].length.reset();
  EXPECT_NEAR(compile(s).get<Tether>()[0].length, Real(0.5), 4 * kEps);
}

TEST(Tether, DegenerateConfigurationsStayFinite) {
  for (Real alpha : {Real(0), Real(1e-3)})
    for (Method method : {Method::xpbd, Method::pbd}) {
      auto s = scene(1);
      s.masses[0] = 1;  // both movable
      s.tethers[0].mat.compliance = alpha;
      const Model m = compile(s);
      State st = make_state(m);
      st.x = {Vec3(1, 1, 1), Vec3(1, 1, 1)};  // coincident
      StepConfig cfg;
      cfg.method = method;
      for (int i = 0; i < 10; ++i) step(m, st, cfg);
      EXPECT_TRUE(test::all_finite(st));
    }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
