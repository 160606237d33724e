// step() (step.cpp): config checks, degenerate runtime configurations, and
// kinematic pins that follow a moving target.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::all_finite;
using test::config_error_names;
using test::kEps;

SceneDesc two_particles() {
  SceneDesc s;
  s.add_particle(Vec3(0, 0, 0), 1);
  s.add_particle(Vec3(1, 0, 0), 1);
  s.distances.push_back(DistanceDesc{0, 1, std::nullopt, {}});
  return s;
}

// ---------------------------------------------------------------------------
// Config errors

TEST(StepConfig, RejectsNonPositiveOrNonFiniteDt) {
  const Model m = compile(two_particles());
  State s = make_state(m);
  StepConfig cfg;
  cfg.dt = 0;
  EXPECT_TRUE(config_error_names(m, s, cfg, {"dt", "0"}));
  cfg.dt = Real(-0.5);
  EXPECT_TRUE(config_error_names(m, s, cfg, {"dt", "-0.5"}));
  cfg.dt = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_TRUE(config_error_names(m, s, cfg, {"dt", "nan"}));
  cfg.dt = std::numeric_limits<Real>::infinity();
  EXPECT_TRUE(config_error_names(m, s, cfg, {"dt", "inf"}));
  // A small negative value must be printed as itself, not rounded to a fixed
  // number of decimals ("-0.000000" would not name the value).
  cfg.dt = Real(-2.5e-7);
  EXPECT_TRUE(config_error_names(m, s, cfg, {"dt", "-2.5e-07"}));
  // The state is untouched by a rejected step.
  EXPECT_EQ(s.x[1], Vec3(1, 0, 0));
  EXPECT_EQ(s.time, Real(0));
}

TEST(StepConfig, RejectsZeroSubstepsOrIterations) {
  const Model m = compile(two_particles());
  State s = make_state(m);
  StepConfig cfg;
  cfg.substeps = 0;
  EXPECT_TRUE(config_error_names(m, s, cfg, {"substeps", "0"}));
  cfg.substeps = -3;
  EXPECT_TRUE(config_error_names(m, s, cfg, {"substeps", "-3"}));
  cfg = StepConfig{};
  cfg.iterations = 0;
  EXPECT_TRUE(config_error_names(m, s, cfg, {"iterations", "0"}));
}

TEST(StepConfig, RejectsBadGravityAndDrag) {
  const Model m = compile(two_particles());
  State s = make_state(m);
  StepConfig cfg;
  cfg.gravity.y() = std::numeric_limits<Real>::infinity();
  EXPECT_TRUE(config_error_names(m, s, cfg, {"gravity"}));
  cfg = StepConfig{};
  cfg.drag = Real(-1);
  EXPECT_TRUE(config_error_names(m, s, cfg, {"drag", "-1"}));
}

TEST(StepConfig, RejectsBadContactSweeps) {
  const Model m = compile(two_particles());
  State s = make_state(m);
  StepConfig cfg;
  cfg.contact_sweeps = -2;
  EXPECT_TRUE(config_error_names(m, s, cfg, {"contact_sweeps", "-2"}));
  cfg = StepConfig{};
  cfg.contact_tolerance = Real(-0.5);
  EXPECT_TRUE(config_error_names(m, s, cfg, {"contact_tolerance", "-0.5"}));
  cfg.contact_tolerance = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_TRUE(config_error_names(m, s, cfg, {"contact_tolerance"}));
}

TEST(StepConfig, RejectsStateOfAnotherModel) {
  const Model m = compile(two_particles());
  SceneDesc other = two_particles();
  other.add_particle(Vec3(2, 0, 0), 1);
  State s = make_state(compile(other));
  EXPECT_TRUE(config_error_names(m, s, StepConfig{}, {"state", "3", "2"}));
}

// ---------------------------------------------------------------------------
// Degenerate runtime configurations: results stay finite, and what happens is
// stated precisely.

// Two coincident particles joined by a distance constraint of rest 1 m. The
// direction of the constraint is undefined, so the kernel skips it: the pair
// falls together under gravity as if unconstrained (lambda stays 0), and
// nothing becomes NaN.
TEST(Degenerate, CoincidentParticlesInDistanceAreSkipped) {
  SceneDesc sd;
  sd.add_particle(Vec3(0, 2, 0), 1);
  sd.add_particle(Vec3(0, 2, 0), 3);
  sd.distances.push_back(DistanceDesc{0, 1, Real(1), {}});
  const Model m = compile(sd);
  State s = make_state(m);
  StepConfig cfg;
  cfg.iterations = 4;
  for (int n = 0; n < 30; ++n) step(m, s, cfg);
  ASSERT_TRUE(all_finite(s));
  EXPECT_EQ(s.x[0], s.x[1]);
  EXPECT_EQ(s.v[0], s.v[1]);
  EXPECT_EQ(s.lambdas<Distance>()[0], Real(0));
  // Free fall: the velocity is -g t (the particles never interact). Round-off:
  // v = (x - x_prev)/h carries the rounding of x (eps * |x|, |x| < 4 m)
  // divided by h, and these errors add up over the 300 substeps.
  const Real h = cfg.dt / Real(cfg.substeps);
  EXPECT_NEAR(s.v[0].y(), -Real(9.81) * s.time, 300 * kEps * 4 / h);
}

// Coincident particles with different velocities separate after one
// prediction; from then on the (stiff) constraint acts and restores the rest
// length. This is a violent but finite correction.
TEST(Degenerate, CoincidentParticlesThatSeparateRecoverRestLength) {
  SceneDesc sd;
  sd.add_particle(Vec3(0, 0, 0), 1, 0, Vec3(0, 0, 0));
  sd.add_particle(Vec3(0, 0, 0), 1, 0, Vec3(1, 0, 0));
  sd.distances.push_back(DistanceDesc{0, 1, Real(1), {}});
  const Model m = compile(sd);
  State s = make_state(m);
  StepConfig cfg;
  cfg.gravity.setZero();
  step(m, s, cfg);
  ASSERT_TRUE(all_finite(s));
  // Two equal masses, compliance 0, one constraint: the last projection
  // leaves it satisfied exactly (to round-off).
  EXPECT_NEAR((s.x[1] - s.x[0]).norm(), 1, 64 * kEps);
}

// A dynamic particle whose (compliant) pin target is exactly its position:
// the direction is undefined, the pin is skipped, and with zero gravity and
// velocity the particle stays exactly where it is.
TEST(Degenerate, PinExactlyOnTargetWithoutLoad) {
  SceneDesc sd;
  sd.add_particle(Vec3(Real(0.3), Real(0.4), Real(-0.2)), 2);
  sd.pins.push_back(PinDesc{0, std::nullopt, Material{Real(1e-3), 0, 1}});
  const Model m = compile(sd);
  State s = make_state(m);
  StepConfig cfg;
  cfg.gravity.setZero();
  for (int n = 0; n < 10; ++n) step(m, s, cfg);
  ASSERT_TRUE(all_finite(s));
  EXPECT_EQ(s.x[0], m.x0[0]);
  EXPECT_EQ(s.v[0], Vec3::Zero());
  EXPECT_EQ(s.lambdas<Pin>()[0], Real(0));
}

// A stiff pin (compliance 0) on a dynamic particle under gravity: every
// substep the prediction moves the particle h^2 g off the target and the
// projection (C = |x - target|, step -C along the unit direction, one
// particle) puts it back exactly, so the particle stays on the target.
TEST(Degenerate, StiffPinUnderGravityHoldsParticleOnTarget) {
  SceneDesc sd;
  const Vec3 target(1, 2, 3);
  sd.add_particle(target, 2);
  sd.pins.push_back(PinDesc{0, std::nullopt, {}});
  const Model m = compile(sd);
  State s = make_state(m);
  const StepConfig cfg;
  for (int n = 0; n < 60; ++n) step(m, s, cfg);
  ASSERT_TRUE(all_finite(s));
  const Real h = cfg.dt / Real(cfg.substeps);
  // Round-off: a few ulps of |target| per substep, not accumulated (the
  // particle is put back on the target every substep).
  EXPECT_LT((s.x[0] - target).norm(), 16 * kEps * target.norm());
  EXPECT_LT(s.v[0].norm(), 16 * kEps * target.norm() / h);
  // The pin carries the weight: force = lambda/h^2 = m g (N). lambda undoes
  // the predicted offset h^2 g, whose round-off is a few eps * |target|:
  // relative error ~ eps |target| / (h^2 g).
  EXPECT_NEAR(std::abs(constraint_force<Pin>(s, 0)), 2 * Real(9.81),
              64 * kEps * target.norm() / (h * h * Real(9.81)) * 2 * Real(9.81));
}

// Constraints between kinematic particles only. With compliance 0 the
// projection has a zero denominator and is skipped (lambda stays 0). With
// compliance alpha > 0 the denominator is alpha/h^2 > 0: the particles cannot
// move (w = 0) and lambda converges to -C h^2/alpha, i.e. the force estimate
// is the spring force -C/alpha between the two fixed anchors. Either way the
// kinematic particles keep their prescribed motion and everything is finite.
TEST(Degenerate, AllKinematicConstraintsAreHarmless) {
  SceneDesc sd;
  sd.add_particle(Vec3(0, 0, 0), 0, Real(0.3), Vec3(Real(0.5), 0, 0));
  sd.add_particle(Vec3(1, 0, 0), 0, Real(0.3), Vec3(Real(0.5), 0, 0));
  sd.distances.push_back(DistanceDesc{0, 1, Real(2), {}});                      // compliance 0
  sd.distances.push_back(DistanceDesc{0, 1, Real(2), Material{Real(1e-3), 0, 1}});  // compliant
  // Overlaps both (contact distance 0.6 m), but is kinematic as well.
  sd.add_particle(Vec3(Real(0.5), Real(0.1), 0), 0, Real(0.3), Vec3(Real(0.5), 0, 0));
  sd.collisions.push_back(CollisionDesc{0, 2, {}});
  sd.planes.push_back(PlaneDesc{Vec3::UnitY(), Real(10), {}});  // every particle "below" it
  const Model m = compile(sd);
  EXPECT_TRUE(m.get<Wall>().empty());  // walls only for movable particles
  State s = make_state(m);
  StepConfig cfg;
  cfg.iterations = 3;
  for (int n = 0; n < 20; ++n) step(m, s, cfg);
  ASSERT_TRUE(all_finite(s));
  // x += h v every substep: 200 roundings of at most eps * |x| (|x| < 2 m).
  const Real tol = 200 * kEps * 2;
  for (Index i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.x[i].x(), m.x0[i].x() + Real(0.5) * s.time, tol);
    EXPECT_EQ(s.x[i].y(), m.x0[i].y());
    EXPECT_EQ(s.v[i].y(), Real(0));
  }
  EXPECT_EQ(s.lambdas<Distance>()[0], Real(0));
  EXPECT_EQ(s.lambdas<Collision>()[0], Real(0));
  // C = 1 - 2 = -1 m, alpha = 1e-3 m/N: spring force -C/alpha = 1000 N (push).
  // Error: the round-off of C (a few eps * 2 m) divided by alpha.
  EXPECT_NEAR(constraint_force<Distance>(s, 1), Real(1000), 64 * kEps * 2 / Real(1e-3));
}

// ---------------------------------------------------------------------------
// Kinematic pins

// A kinematic particle (mass 0) with a pin follows the target set before each
// step: at the end of the step it is exactly on the target, and its velocity
// is the target's velocity. A dynamic particle hangs from it by a stiff
// distance constraint; it must not disturb the kinematic one.
TEST(KinematicPin, FollowsLinearlyMovingTargetExactly) {
  SceneDesc sd;
  const Vec3 p0(Real(0.2), 1, Real(-0.4));
  const Vec3 u(Real(1.5), Real(-0.5), Real(0.25));  // m/s, target velocity
  sd.add_particle(p0, 0);
  sd.add_particle(p0 - Vec3(0, Real(0.5), 0), 1);
  sd.pins.push_back(PinDesc{0, std::nullopt, {}});
  sd.distances.push_back(DistanceDesc{0, 1, std::nullopt, {}});
  const Model m = compile(sd);
  State s = make_state(m);
  StepConfig cfg;
  cfg.substeps = 7;
  cfg.iterations = 2;
  const Real h = cfg.dt / Real(cfg.substeps);
  for (int n = 1; n <= 40; ++n) {
    const Vec3 target = p0 + (Real(n) * cfg.dt) * u;
    s.pin_target[0] = target;
    step(m, s, cfg);
    ASSERT_EQ(s.x[0], target) << "step " << n;
    // v = (x - x_prev)/h of the last substep, with x and x_prev on the
    // linearly interpolated target: u up to the rounding of the targets
    // (a few eps * |target|) divided by h.
    EXPECT_LT((s.v[0] - u).norm(), 16 * kEps * (target.norm() + 1) / h) << "step " << n;
  }
  ASSERT_TRUE(all_finite(s));
}

// Same on a circle, where the target velocity over one step is the secant
// (T_{n+1} - T_n)/dt: the particle is on the target at every step end.
TEST(KinematicPin, FollowsCircularTargetExactly) {
  SceneDesc sd;
  const Real radius = Real(0.7), omega = Real(3);  // m, rad/s
  sd.add_particle(Vec3(radius, 0, 0), 0);
  sd.pins.push_back(PinDesc{0, std::nullopt, {}});
  const Model m = compile(sd);
  State s = make_state(m);
  StepConfig cfg;
  cfg.substeps = 5;
  const Real h = cfg.dt / Real(cfg.substeps);
  Vec3 prev = m.x0[0];
  for (int n = 1; n <= 100; ++n) {
    const Real t = Real(n) * cfg.dt;
    const Vec3 target(radius * std::cos(omega * t), radius * std::sin(omega * t), 0);
    s.pin_target[0] = target;
    step(m, s, cfg);
    ASSERT_EQ(s.x[0], target) << "step " << n;
    const Vec3 secant = (target - prev) / cfg.dt;
    EXPECT_LT((s.v[0] - secant).norm(), 16 * kEps * radius / h) << "step " << n;
    prev = target;
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
