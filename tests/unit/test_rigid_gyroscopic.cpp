// A free rigid body's spin (xpbd::rigid::predict_bodies' gyroscopic term),
// without Bullet. Closed form: with no torque, the angular momentum
// L = R I R^T w is constant and so is the kinetic energy (1/2) w.L (Euler's
// equations); about its largest or smallest principal axis a spin stays
// near that axis. The implicit midpoint rule keeps the energy to round-off
// and L to first order in h w.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "xpbd/rigid_solve.hpp"
#include "xpbd/xpbd.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;

Vec3 momentum(const xpbd::RigidBody& b) {
  const Vec3 wl = b.q.conjugate() * b.w;
  return b.q * Vec3(wl.array() / b.inv_inertia.array());
}

Real energy(const xpbd::RigidBody& b) { return Real(0.5) * b.w.dot(momentum(b)); }

// The squeeze application's bar: 2 kg, 1.2 x 0.06 x 0.06 m (principal
// inertias 0.0012, 0.2406, 0.2406 kg m^2), spinning at 50 rad/s about its
// long axis while that axis turns at 4 rad/s, as after the bar's far end
// landed on its edge (docs/squeeze-surface-edges.md). Two seconds at 60 Hz
// x 10 substeps, through xpbd::step (no particles near, no gravity).
xpbd::RigidBody bar_after(int steps) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3(5, 5, 5), 1);  // far away: no interaction
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  xpbd::RigidBody b;
  b.inv_mass = Real(0.5);
  const Real ix = Real(2) * (Real(0.06) * Real(0.06) * 2) / 12, iy = Real(2) * (Real(1.2) * Real(1.2) + Real(0.06) * Real(0.06)) / 12;
  b.inv_inertia = Vec3(1 / ix, 1 / iy, 1 / iy);
  b.w = Vec3(50, 0, 4);
  s.bodies.push_back(b);
  xpbd::StepConfig cfg;
  cfg.gravity.setZero();
  cfg.substeps = 10;
  for (int k = 0; k < steps; ++k) xpbd::step(m, s, cfg);
  return s.bodies[0];
}

TEST(RigidGyroscopic, FreeSpinningBarKeepsItsAngularMomentumAndEnergy) {
  xpbd::RigidBody b0;
  {
    const Real ix = Real(2) * (Real(0.06) * Real(0.06) * 2) / 12, iy = Real(2) * (Real(1.2) * Real(1.2) + Real(0.06) * Real(0.06)) / 12;
    b0.inv_inertia = Vec3(1 / ix, 1 / iy, 1 / iy);
    b0.w = Vec3(50, 0, 4);
  }
  const Vec3 l0 = momentum(b0);
  const Real e0 = energy(b0);
  Real worst_l = 0, worst_e = 0;
  for (const int steps : {1, 30, 120}) {
    const xpbd::RigidBody b = bar_after(steps);
    worst_l = std::max(worst_l, (momentum(b) - l0).norm() / l0.norm());
    worst_e = std::max(worst_e, std::abs(energy(b) - e0) / e0);
  }
  std::printf("free bar spinning at 50 rad/s about its long axis, 4 rad/s across: angular momentum off by at most "
              "%.3g, kinetic energy by at most %.3g (relative) over 2 s\n",
              double(worst_l), double(worst_e));
  // Measured over the same three checkpoints (2026-11-29): without the term
  // (w fixed in the world) L was off by up to 0.80 and the energy kept; with
  // the term by backward Euler (Bullet's implicit form) 0.98 and 0.56; with
  // the old read-back of w, (2/h) vec(dq), and no term, 1.75 and 0.68 (the
  // spin decays by sqrt(1 + (h w / 2)^2) per substep). With the midpoint
  // rule: 0.070 and 3.6e-13 in double. L's drift is first order in h w
  // (0.083 here): the orientation's step, not the spin's.
  EXPECT_LT(worst_l, Real(0.1));
  const Real roundoff = std::max(Real(1e-9), Real(1e4) * xpbd::kEpsilon);
  EXPECT_LT(worst_e, roundoff);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
