// Penetration against a fixed (kinematic) triangle:
//  - a particle dropped from above comes to rest on the +n side exactly at
//    the thickness (stiff contact), or at thickness - alpha*m*g (compliant
//    contact: converged XPBD is backward Euler, whose fixed point is the
//    static force balance C/alpha = -m g);
//  - a particle that starts below and is thrown upward through the triangle
//    within one step is pushed back below, never through.
#include <gtest/gtest.h>

#include <cmath>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;
constexpr Real kThickness = Real(0.05);  // m

// Kinematic triangle in the plane y = 0 with normal +y:
// (x2 - x1) x (x3 - x1) = (1, 0, 2) x (2, 0, 0) = (0, 4, 0).
SceneDesc scene(const Vec3& start, const Vec3& v0, Real compliance) {
  SceneDesc s;
  s.add_particle(start, 1, 0, v0);
  s.add_particle(Vec3(-1, 0, -1), 0);
  s.add_particle(Vec3(0, 0, 1), 0);
  s.add_particle(Vec3(1, 0, -1), 0);
  s.penetrations.push_back(PenetrationDesc{{0, 1, 2, 3}, kThickness, Material{compliance, 0, 1}});
  return s;
}

TEST(PenetrationFall, StiffContactRestsAtThickness) {
  const Model m = compile(scene(Vec3(Real(0.1), 1, Real(-0.2)), Vec3::Zero(), 0));
  State st = make_state(m);
  StepConfig cfg;  // 60 Hz, 10 substeps, g = 9.81
  for (int i = 0; i < 120; ++i) {
    step(m, st, cfg);
    // The projection restores C = 0 exactly (one linear constraint, one
    // particle), so the end-of-step height never goes below the thickness
    // by more than round-off.
    ASSERT_GE(st.x[0].y(), kThickness - 16 * kEps) << "step " << i;
  }
  EXPECT_NEAR(st.x[0].y(), kThickness, 16 * kEps);
  EXPECT_NEAR(st.v[0].y(), 0, 16 * kEps / (cfg.dt / cfg.substeps));
  // The contact normal is +y only: no sideways drift.
  EXPECT_EQ(st.x[0].x(), Real(0.1));
  EXPECT_EQ(st.x[0].z(), Real(-0.2));
}

TEST(PenetrationFall, CompliantContactSinksByAlphaMG) {
  // Static balance of the contact "spring": C = -alpha m g. Starting just
  // touching, the particle oscillates about that depth with amplitude
  // alpha m g; each substep damps it by 1/sqrt(1 + (omega h)^2) with
  // omega = 1/sqrt(m alpha) = 100 rad/s, h = 1/600 s: after 3 s (1800
  // substeps) the residual is ~ e^-25 of the amplitude. Tolerance 1e-6 of the
  // depth plus round-off.
  const Real alpha = Real(1e-4);  // m/N
  const Model m = compile(scene(Vec3(0, kThickness, 0), Vec3::Zero(), alpha));
  State st = make_state(m);
  StepConfig cfg;
  for (int i = 0; i < 180; ++i) step(m, st, cfg);
  const Real depth = alpha * 1 * -cfg.gravity.y();
  EXPECT_NEAR(st.x[0].y(), kThickness - depth, Real(1e-6) * depth + 16 * kEps);
  // The multiplier gives the contact force m g (N), pushing up.
  EXPECT_NEAR(constraint_force<Penetration>(st, 0), -cfg.gravity.y(),
              Real(1e-5) * -cfg.gravity.y() + Real(1e-6));
}

TEST(PenetrationFall, ParticleBelowStaysBelow) {
  // Thrown up from 0.5 m below at 60 m/s: with one substep the predicted
  // position is 0.5 m above the triangle; the side recorded at the start of
  // the step (-1) pushes it back to -thickness. With 10 substeps the crossing
  // happens inside one substep. Either way it must end every step below.
  for (int substeps : {1, 10}) {
    const Model m = compile(scene(Vec3(0, Real(-0.5), 0), Vec3(0, 60, 0), 0));
    State st = make_state(m);
    StepConfig cfg;
    cfg.substeps = substeps;
    for (int i = 0; i < 60; ++i) {
      step(m, st, cfg);
      ASSERT_LE(st.x[0].y(), -kThickness + 16 * kEps) << "substeps " << substeps << " step " << i;
      ASSERT_EQ(st.penetration_side[0], Real(-1));
    }
    // It then falls away freely: below the contact and moving down.
    EXPECT_LT(st.x[0].y(), -kThickness);
    EXPECT_LT(st.v[0].y(), 0);
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
