// Particle-particle collision found by the spatial hash (spatial_hash.hpp):
// closed-form checks.
//  - Head-on collision of two particles: XPBD contacts are perfectly
//    inelastic (velocities come from the projected positions, there is no
//    restitution), so after the contact both move with the centre-of-mass
//    velocity (m_a v_a + m_b v_b)/(m_a + m_b), exactly d apart.
//  - A box of particles with random velocities and masses, collisions only,
//    no gravity: linear momentum is conserved to round-off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

struct HeadOn {
  Real ma, mb;  // kg
  Real va, vb;  // m/s along x; a starts at x = -0.5 m, b at +0.5 m
};

// Two particles on the x axis approaching each other, collision distance
// d = 0.1 m, 60 Hz, 10 substeps, no gravity, for 1 s.
void head_on(const HeadOn& c) {
  const Real d = Real(0.1);
  SceneDesc sd;
  sd.add_particle(Vec3(Real(-0.5), 0, 0), c.ma, 0, Vec3(c.va, 0, 0));
  sd.add_particle(Vec3(Real(0.5), 0, 0), c.mb, 0, Vec3(c.vb, 0, 0));
  sd.self_collision.enabled = true;
  sd.self_collision.distance = d;
  const Model m = compile(sd);
  State s = make_state(m);
  StepConfig cfg;
  cfg.gravity.setZero();
  const Real M = c.ma + c.mb;
  const Real vf = (c.ma * c.va + c.mb * c.vb) / M;        // m/s, common final velocity
  const Real com0 = (c.ma * Real(-0.5) + c.mb * Real(0.5)) / M;  // m
  const int steps = 60;
  // Round-off: every substep rounds each coordinate (|x| < X = 3 m) once in
  // the prediction and once per projection; errors add up over the
  // n = 600 substeps at most linearly in position (the contact removes the
  // relative part every substep).
  const Real X = 3, n_sub = Real(steps * cfg.substeps);
  const Real tol_x = 4 * n_sub * kEps * X;
  Real min_gap = 1e9;
  for (int k = 1; k <= steps; ++k) {
    step(m, s, cfg);
    const Real gap = s.x[1].x() - s.x[0].x();
    min_gap = std::min(min_gap, gap);
    // Never closer than d, beyond round-off (the only contact is projected
    // exactly: one linear constraint along x).
    ASSERT_GE(gap, d - 16 * kEps * X) << "step " << k;
  }
  const Real h = cfg.dt / Real(cfg.substeps);
  EXPECT_NEAR(s.x[1].x() - s.x[0].x(), d, 16 * kEps * X);
  EXPECT_NEAR(s.v[0].x(), vf, 16 * kEps * X / h);
  EXPECT_NEAR(s.v[1].x(), vf, 16 * kEps * X / h);
  // The centre of mass moves uniformly; each particle sits at its share of
  // d from it (b at m_a d / M on one side, a at m_b d / M on the other).
  const Real com = com0 + vf * s.time;
  EXPECT_NEAR(s.x[0].x(), com - c.mb * d / M, tol_x);
  EXPECT_NEAR(s.x[1].x(), com + c.ma * d / M, tol_x);
  // Straight line: no motion off the axis.
  EXPECT_EQ(s.x[0].y(), 0);
  EXPECT_EQ(s.x[1].z(), 0);
  std::printf("head-on m = (%g, %g) kg, v = (%g, %g) m/s: final gap - d = %.3g m, v = (%.17g, "
              "%.17g) m/s, expected %.17g\n",
              double(c.ma), double(c.mb), double(c.va), double(c.vb), double(s.x[1].x() - s.x[0].x() - d),
              double(s.v[0].x()), double(s.v[1].x()), double(vf));
}

TEST(ParticleCollision, HeadOnEqualMassesStopAtContactDistance) {
  head_on({1, 1, 3, -3});
}

TEST(ParticleCollision, HeadOnUnequalMassesMoveTogether) {
  // Relative speed 16 m/s: 0.27 m per step, more than twice d, so the
  // particles would pass each other within one step unless the pair is a
  // candidate before they touch (the travel margin of the hash query:
  // at the start of the step in which they meet they are 0.2 m apart, twice
  // d). Per substep they close 0.027 m < d, so the substeps see the contact.
  head_on({1, 3, 10, -6});
}

TEST(ParticleCollision, CollisionsAloneConserveLinearMomentum) {
  // 5 x 5 x 5 particles 1.02 d apart (not touching), random masses, no
  // gravity, velocities converging on the centre (4 1/s times the offset)
  // plus random ones up to 0.3 m/s per axis: the box collapses onto itself
  // and flies apart through many collisions.
  // Every projection moves a by w_a dlambda n and b by -w_b dlambda n, so
  // sum m x changes by dlambda (n - n) = 0: linear momentum is exact in
  // exact arithmetic, and what remains is round-off.
  const Real d = Real(0.05);
  SceneDesc sd;
  std::mt19937 rng(7);
  std::uniform_real_distribution<Real> mass(Real(0.2), Real(2)), vel(Real(-0.3), Real(0.3));
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i)
        sd.add_particle(Real(1.02) * d * Vec3(Real(i), Real(j), Real(k)), mass(rng), 0,
                        -Real(4) * Real(1.02) * d * Vec3(Real(i - 2), Real(j - 2), Real(k - 2)) +
                            Vec3(vel(rng), vel(rng), vel(rng)));
  sd.self_collision.enabled = true;
  sd.self_collision.distance = d;
  const Model m = compile(sd);
  State s = make_state(m);
  StepConfig cfg;
  cfg.gravity.setZero();
  cfg.iterations = 2;
  const Real h = cfg.dt / Real(cfg.substeps);
  const Vec3 p0 = linear_momentum(m, s);
  const Real M = total_mass(m);
  const Index n = m.num_particles();

  // Round-off bound, as in test_momentum.cpp: per substep each particle's
  // position is rounded once in the prediction and once per projection
  // touching it, at most R = 1 + K * iterations times, K = the most pairs a
  // particle is in this step; each rounding is at most eps * X (X = largest
  // |coordinate|) and changes the momentum by m_i eps X / h, all of one sign
  // in the worst case.
  const int steps = 120;
  Real bound = 0, worst = 0;
  int contact_steps = 0;
  std::vector<int> per_particle(static_cast<std::size_t>(n));
  for (int k = 1; k <= steps; ++k) {
    step(m, s, cfg);
    std::fill(per_particle.begin(), per_particle.end(), 0);
    for (const Collision& c : s.self_collision.pairs) {
      ++per_particle[std::size_t(c.p[0])];
      ++per_particle[std::size_t(c.p[1])];
    }
    const int K = *std::max_element(per_particle.begin(), per_particle.end());
    Real X = 0;
    for (const Vec3& x : s.x) X = std::max(X, x.cwiseAbs().maxCoeff());
    const Real R = 1 + Real(K * cfg.iterations);
    bound += Real(cfg.substeps) * R * kEps * X * M / h;
    const Real dp = (linear_momentum(m, s) - p0).norm();
    ASSERT_LE(dp, bound) << "step " << k;
    worst = std::max(worst, dp);
    bool pushing = false;
    for (Real l : s.self_collision.lambda) pushing = pushing || l > 0;
    contact_steps += pushing;
  }
  ASSERT_TRUE(test::all_finite(s));
  // Collisions did happen, in many steps.
  EXPECT_GT(contact_steps, 10);
  std::printf("box of %d particles: |p0| = %.6f kg m/s, max |p - p0| = %.3g kg m/s (bound at the "
              "end %.3g), %d steps with contacts\n",
              int(n), double(p0.norm()), double(worst), double(bound), contact_steps);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
