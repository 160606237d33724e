// Free fall without constraints (docs/design.md section 6, row 1).
//
// Reference: the discrete solution of symplectic Euler with substep h. With k
// counting substeps (not steps), one substep is
//   v_k = v_{k-1} + h g,   x_k = x_{k-1} + h v_k
// so v_k = v0 + k h g and
//   x_n = x0 + h sum_{k=1..n} (v0 + k h g) = x0 + v0 n h + g h^2 n(n+1)/2.
// With S substeps per step, after `steps` steps n = steps * S and t = n h.
// For g = (0, -9.81, 0) the y component is y0 + v0 t - 9.81 h^2 n(n+1)/2,
// the formula of docs/design.md. (The continuous solution differs by g h t / 2,
// about 1e-2 m here, explicit Euler by g h t: the test separates all three
// by eight orders of magnitude.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

TEST(FreeFall, MatchesDiscreteSymplecticEulerToRoundOff) {
  SceneDesc sd;
  // Different masses (must not matter) and initial velocities.
  sd.add_particle(Vec3(0, 10, 0), 1, 0, Vec3(0, 0, 0));
  sd.add_particle(Vec3(Real(-1), 2, Real(0.5)), Real(0.01), 0, Vec3(Real(1.5), 4, Real(-2)));
  sd.add_particle(Vec3(3, 0, Real(-2)), 250, 0, Vec3(Real(-0.3), Real(-1), Real(0.7)));
  const Model m = compile(sd);
  State s = make_state(m);
  StepConfig cfg;
  cfg.substeps = 7;
  cfg.gravity = Vec3(Real(1.5), Real(-9.81), Real(0.5));  // tilted on purpose, m/s^2
  const Real h = cfg.dt / Real(cfg.substeps);
  const int steps = 60;

  // Round-off bound. Each substep rounds x_k (|error| <= eps X, X = largest
  // coordinate magnitude, < 25 m here). v = (x_k - x_{k-1})/h absorbs that
  // error, so it persists in v and is integrated by every later substep:
  // after n substeps the position error is at most n(n+1)/2 eps X and the
  // velocity error n eps X / h (worst case, all errors of one sign).
  const Real X = 25;
  Real worst_x = 0, worst_v = 0;
  for (int step_i = 1; step_i <= steps; ++step_i) {
    step(m, s, cfg);
    const Real n = Real(step_i * cfg.substeps);
    const Real x_tol = n * (n + 1) / 2 * kEps * X;
    const Real v_tol = n * kEps * X / h;
    for (Index i = 0; i < m.num_particles(); ++i) {
      const Vec3 x_ref = m.x0[i] + (n * h) * m.v0[i] + (h * h * n * (n + 1) / 2) * cfg.gravity;
      const Vec3 v_ref = m.v0[i] + (n * h) * cfg.gravity;
      const Real ex = (s.x[i] - x_ref).cwiseAbs().maxCoeff();
      const Real ev = (s.v[i] - v_ref).cwiseAbs().maxCoeff();
      ASSERT_LE(ex, x_tol) << "particle " << i << " step " << step_i;
      ASSERT_LE(ev, v_tol) << "particle " << i << " step " << step_i;
      worst_x = std::max(worst_x, ex);
      worst_v = std::max(worst_v, ev);
    }
  }
  RecordProperty("max_position_error_m", std::to_string(worst_x));
  std::printf("free fall: max |x - x_ref| = %.3g m, max |v - v_ref| = %.3g m/s over %d substeps\n",
              double(worst_x), double(worst_v), steps * cfg.substeps);
}

// Kinematic particles (mass 0) ignore gravity and keep their velocity.
TEST(FreeFall, KinematicParticleMovesAtConstantVelocity) {
  SceneDesc sd;
  sd.add_particle(Vec3(1, 2, 3), 0, 0, Vec3(Real(0.5), Real(-0.25), 1));
  const Model m = compile(sd);
  State s = make_state(m);
  const StepConfig cfg;
  for (int n = 0; n < 60; ++n) step(m, s, cfg);
  // x += h v, 600 times: at most 600 roundings of eps * |x| (|x| < 5 m).
  EXPECT_LT((s.x[0] - (m.x0[0] + s.time * m.v0[0])).norm(), 600 * kEps * 5);
  // v = (x - x_prev)/h: the rounding of x divided by h.
  EXPECT_NEAR(s.v[0].y(), Real(-0.25), 4 * kEps * 5 / (cfg.dt / Real(cfg.substeps)));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
