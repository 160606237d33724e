// Linear momentum of a free system with internal constraints only (docs/design.md
// section 6, row 5).
//
// Every internal constraint here (Distance, Collision) depends only on
// differences of positions, so its gradients sum to zero: sum_i grad_i C = 0.
// A projection moves particle i by w_i grad_i C dlambda, changing
// sum_i m_i x_i by dlambda sum_i grad_i C = 0, with or without damping (which
// only changes dlambda). So momentum sum_i m_i (x_i - x_prev_i)/h is
// conserved exactly in exact arithmetic; what remains is round-off.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

TEST(Momentum, InternalConstraintsConserveLinearMomentum) {
  SceneDesc sd;
  ClothGridDesc c;
  c.nx = 6;
  c.ny = 6;
  c.size_u = c.size_v = Real(0.5);
  c.radius = Real(0.15);  // m
  c.stretch = Material{Real(1e-5), Real(0.5), 1};  // m/N, N s/m: damped kernel too
  c.shear_mat = Material{Real(1e-4), 0, 1};
  c.bend_mat = Material{Real(1e-3), 0, 1};
  add_cloth_grid(sd, c);
  const int n = sd.num_particles();
  std::mt19937 rng(2024);
  std::uniform_real_distribution<Real> mass(Real(0.2), Real(2)), vel(-1, 1);
  sd.velocities.assign(std::size_t(n), Vec3::Zero());
  for (int i = 0; i < n; ++i) {
    sd.masses[std::size_t(i)] = mass(rng);  // unequal masses: the weighting matters
    sd.velocities[std::size_t(i)] = Vec3(vel(rng), vel(rng), vel(rng));
  }
  // Collisions between particles two apart along the diagonal: contact
  // distance 0.3 m vs initial distance 0.283 m (spacing 0.1 m), so they start
  // engaged and fight the shear edges.
  for (int j = 0; j + 2 < c.ny; ++j)
    for (int i = 0; i + 2 < c.nx; ++i)
      sd.collisions.push_back(CollisionDesc{j * c.nx + i, (j + 2) * c.nx + i + 2, {}});
  const Model m = compile(sd);
  State s = make_state(m);
  StepConfig cfg;
  cfg.gravity.setZero();
  cfg.substeps = 10;
  cfg.iterations = 2;
  const Real h = cfg.dt / Real(cfg.substeps);
  const Vec3 p0 = linear_momentum(m, s);
  const Real M = total_mass(m);

  // Round-off bound. Per substep, each particle's position is rounded once in
  // the prediction and once per projection touching it (at most 12 cloth
  // edges + 1 collision, per iteration): R = 1 + 13 * iterations roundings of
  // at most eps * X (X = largest |coordinate|, < 5 m here). Each contributes
  // m_i * eps * X / h to the momentum, with all signs equal in the worst case.
  const int steps = 200;
  const Real R = 1 + 13 * Real(cfg.iterations);
  const Real X = 5;
  Real worst = 0;
  Real max_contact = 0;  // largest collision multiplier seen, kg m
  for (int k = 1; k <= steps; ++k) {
    step(m, s, cfg);
    for (Real l : s.lambdas<Collision>()) max_contact = std::max(max_contact, l);
    const Real bound = Real(k * cfg.substeps) * R * kEps * X * M / h;
    const Real dp = (linear_momentum(m, s) - p0).norm();
    ASSERT_LE(dp, bound) << "step " << k;
    worst = std::max(worst, dp);
  }
  ASSERT_TRUE(test::all_finite(s));
  // The system did deform and the constraints did act (otherwise the test
  // would be trivial): the collision and distance multipliers are non-zero.
  Real lsum = 0;
  for (Real l : s.lambdas<Distance>()) lsum += std::abs(l);
  EXPECT_GT(lsum, Real(0));
  EXPECT_GT(max_contact, Real(0));
  std::printf("momentum: |p0| = %.6f kg m/s, max |p - p0| = %.3g kg m/s over %d steps\n",
              double(p0.norm()), double(worst), steps);
  // Centre of mass moves uniformly: x_com(t) = x_com(0) + p0 t / M.
  Vec3 com0 = Vec3::Zero(), com = Vec3::Zero();
  for (Index i = 0; i < m.num_particles(); ++i) {
    com0 += m.x0[i] / m.inv_mass[i];
    com += s.x[i] / m.inv_mass[i];
  }
  // Bound: the per-substep roundings above (R eps X each) also feed the
  // velocities, so the position error grows at most like n^2/2 R eps X after
  // n substeps.
  const Real n_sub = Real(steps * cfg.substeps);
  EXPECT_LT((com / M - (com0 / M + (s.time / M) * p0)).norm(), n_sub * n_sub / 2 * R * kEps * X);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
