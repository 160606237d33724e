// Dihedral bending on a single hinge whose edge is kinematic and whose wings
// are point masses kept rigid by stiff distance constraints to both edge
// particles, so each wing can only rotate about the hinge:
//  - a bent hinge returns to its rest angle (stiff, and compliant + damped),
//    from flat, bent and fully folded starts;
//  - with compliance alpha and one wing of mass m at height r the wing is a
//    torsional oscillator of stiffness 1/alpha (N*m/rad) and inertia m r^2:
//    period 2 pi sqrt(alpha m r^2), exact for any amplitude because C is
//    linear in the rotation angle.
// Both in array order and with StepConfig::coloured (where XPBD runs the
// hinges over their compiled stream, dihedral_stream.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;
constexpr Real kPi = std::numbers::pi_v<Real>;
constexpr Real kR = 1;        // m, wing height over the hinge edge
constexpr Real kMass = Real(0.1);  // kg, per wing

// Wing positions at hinge angle phi (sign convention of DihedralBending:
// wing 2 fixed in the xy plane; wing 3 rotated by -phi from the flat pose).
Vec3 wing3(Real phi) { return Vec3(Real(0.5), -kR * std::cos(-phi), kR * std::sin(-phi)); }

// Hinge at angle phi, each wing rotated by half of it (raising both wings
// towards +z folds the hinge to phi < 0).
std::vector<Vec3> hinge(Real phi) {
  const Real a = -phi / 2;
  return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(Real(0.5), kR * std::cos(a), kR * std::sin(a)),
          Vec3(Real(0.5), -kR * std::cos(a), kR * std::sin(a))};
}

SceneDesc scene(Real rest, const Material& mat, bool wing2_kinematic) {
  SceneDesc s;
  const auto x = hinge(rest);
  s.add_particle(x[0], 0);
  s.add_particle(x[1], 0);
  s.add_particle(x[2], wing2_kinematic ? 0 : kMass);
  s.add_particle(x[3], kMass);
  for (Index w : {2, 3})
    for (Index e : {0, 1}) s.distances.push_back(DistanceDesc{e, w, std::nullopt, {}});
  s.dihedral_bends.push_back(DihedralBendingDesc{{0, 1, 2, 3}, std::nullopt, mat});
  return s;
}

Real angle(const State& st) {
  Real phi = 0;
  EXPECT_TRUE(DihedralBending::angle({0, 1, 2, 3}, st.x.data(), phi));
  return phi;
}

TEST(DihedralBendingRest, ReturnsToRestAngle) {
  // Stiff: each substep projects onto C = 0 (and the distances), so it is at
  // rest after the first step up to the Gauss-Seidel coupling with the
  // distances, which 4 iterations over 60 steps remove. Compliant: hinge
  // stiffness k = 1/alpha = 10 N*m/rad, inertia 2 m r^2 = 0.2 kg*m^2 for the
  // symmetric mode, damping beta = 1 J*s/rad^2 (damping ratio
  // beta/(2 sqrt(k I)) = 0.35): the error decays like exp(-beta t/(2I)) =
  // exp(-2.5 t), below 1e-9 rad after 8 s. Tolerance 1e-6 rad.
  const Material stiff{0, 0, 1};
  const Material soft{Real(0.1), 1, 1};
  for (bool coloured : {false, true})
    for (Real rest : {Real(0), Real(1), Real(-2.5)})
      for (const Material& mat : {stiff, soft})
        for (Real start : {rest + Real(0.8), rest - Real(0.6), kPi}) {
          const Model m = compile(scene(rest, mat, false));
          State st = make_state(m);
          st.x = hinge(start);
          StepConfig cfg;
          cfg.gravity = Vec3::Zero();
          cfg.iterations = 4;
          cfg.coloured = coloured;
          for (int i = 0; i < 480; ++i) step(m, st, cfg);
          EXPECT_NEAR(detail::wrap_angle(angle(st) - rest), 0, Real(1e-6))
              << "rest " << rest << " start " << start << " compliance " << mat.compliance << " coloured "
              << coloured;
          EXPECT_TRUE(test::all_finite(st));
        }
}

TEST(DihedralBendingRest, TorsionalPeriodMatchesCompliance) {
  // One movable wing: I = m r^2 = 0.1 kg*m^2, k = 1/alpha = 10 N*m/rad:
  // T = 2 pi sqrt(I/k) = 0.6283 s. XPBD with converged iterations is backward
  // Euler, whose phase per step is atan(omega h) instead of omega h: relative
  // period error (omega h)^2/3 = 9e-5 at h = 1/600 s (omega = 10 rad/s).
  // Iterations 8 keep the distance coupling converged. Tolerance 1e-3.
  const Real alpha = Real(0.1);
  const Model m = compile(scene(0, Material{alpha, 0, 1}, true));
  for (bool coloured : {false, true}) {
    State st = make_state(m);
    st.x[3] = wing3(Real(0.5));
    StepConfig cfg;
    cfg.gravity = Vec3::Zero();
    cfg.iterations = 8;
    cfg.coloured = coloured;
    std::vector<double> t, phi;
    for (int i = 0; i < 300; ++i) {
      step(m, st, cfg);
      t.push_back(double(st.time));
      phi.push_back(double(angle(st)));
    }
    const double period = test::mean_period(test::zero_crossings(t, phi, 1));
    const double expected = 2 * std::numbers::pi * std::sqrt(double(alpha) * double(kMass) * kR * kR);
    std::printf("dihedral torsional period (coloured %d): measured %.6f s, expected %.6f s (rel. error %.2e)\n",
                int(coloured), period, expected, period / expected - 1);
    EXPECT_NEAR(period / expected, 1, 1e-3) << "coloured " << coloured;
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
