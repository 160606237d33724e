// Tetrahedral volume:
//  - a squashed tetrahedron (all four particles free) returns to its rest
//    volume, and an inverted one is pushed back through to the positive rest
//    volume, not to the mirror image; linear momentum stays zero (internal
//    constraint, gradients sum to zero);
//  - static load: base kinematic, apex loaded by a force F along the base
//    normal. V is linear in the apex, grad V = (A_b/3) n, so the balance
//    F = (A_b/3) (-C/alpha) gives C = -3 alpha F / A_b exactly: the
//    compliance is the volume compliance in m^6/J.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

const std::vector<Vec3> kRest = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
constexpr Real kV0 = Real(1) / 6;  // m^3

Real volume(const State& st) { return TetVolume::volume(st.x[0], st.x[1], st.x[2], st.x[3]); }

TEST(TetVolumeRecovery, SquashedAndInvertedReturnToRestVolume) {
  // No edges: only the volume is constrained, so the shape keeps drifting
  // along volume-preserving motions; a velocity drag of 2 /s settles it.
  // Stiff: each iteration is one Newton step on the cubic C; compliant
  // (alpha = 1e-3 m^6/J): the volume mode is a drag-damped oscillator whose
  // amplitude decays at least like exp(-drag t / 2) = e^-20 after 20 s.
  // Tolerance 1e-6 relative to V0 for both.
  // Momentum: every projection moves the particles by w_i dlambda g_i with
  // sum g_i = 0, so momentum changes only by round-off, ~eps |x| / h per
  // substep; over N = 12000 substeps (h = 1/600 s) that is at most
  // N eps * 600 = 1.6e-9 (double) kg*m/s; tolerance 16 N eps / h.
  const Material stiff{0, 0, 1};
  const Material soft{Real(1e-3), 0, 1};
  for (const Material& mat : {stiff, soft})
    for (Real apex_z : {Real(0.2), Real(-0.5), Real(0)}) {  // squashed, inverted, flat
      SceneDesc s;
      for (const Vec3& p : kRest) s.add_particle(p, 1);
      s.tets.push_back(TetVolumeDesc{{0, 1, 2, 3}, std::nullopt, mat});
      const Model m = compile(s);
      State st = make_state(m);
      st.x[3].z() = apex_z;
      StepConfig cfg;
      cfg.gravity = Vec3::Zero();
      cfg.iterations = 4;
      cfg.drag = 2;
      const int steps = 1200;
      for (int i = 0; i < steps; ++i) step(m, st, cfg);
      EXPECT_NEAR(volume(st) / kV0, 1, Real(1e-6)) << "apex z " << apex_z << " alpha " << mat.compliance;
      const Real h = cfg.dt / Real(cfg.substeps);
      EXPECT_LE(linear_momentum(m, st).norm(), 16 * steps * cfg.substeps * kEps / h)
          << "apex z " << apex_z;
    }
}

TEST(TetVolumeRecovery, StaticLoadMatchesCompliance) {
  // Base (0,0,0), (1,0,0), (0,1,0) kinematic, area A_b = 1/2; apex of mass
  // 1 kg at (0,0,1) pushed down by F = 2 N. Expected C = -3 alpha F / A_b.
  // The apex is a damped oscillator: stiffness (A_b/3)^2/alpha = 27.8 N/m at
  // alpha = 1e-3 m^6/J (omega = 5.27 rad/s), damping coefficient
  // beta (A_b/3)^2 = 5.6 N*s/m with beta = 200 J*s/m^6 (ratio 0.53, decay
  // rate 2.8 /s): after 10 s the transient is ~e^-28. Tolerance 1e-6 relative.
  const Real alpha = Real(1e-3), force = 2, area = Real(0.5);
  SceneDesc s;
  for (int i = 0; i < 3; ++i) s.add_particle(kRest[i], 0);
  s.add_particle(kRest[3], 1);
  s.tets.push_back(TetVolumeDesc{{0, 1, 2, 3}, std::nullopt, Material{alpha, 200, 1}});
  const Model m = compile(s);
  State st = make_state(m);
  st.f_ext.assign(4, Vec3::Zero());
  st.f_ext[3] = Vec3(0, 0, -force);
  StepConfig cfg;
  cfg.gravity = Vec3::Zero();
  for (int i = 0; i < 600; ++i) step(m, st, cfg);
  const Real expected_c = -3 * alpha * force / area;
  EXPECT_NEAR((volume(st) - kV0) / expected_c, 1, Real(1e-6));
  // The apex moves along the normal only.
  EXPECT_NEAR(st.x[3].x(), 0, 16 * kEps);
  EXPECT_NEAR(st.x[3].y(), 0, 16 * kEps);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
