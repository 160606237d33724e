// Energy of a compliant spring (docs/design.md section 6, notes): XPBD is backward
// Euler, which never adds energy and loses some through numerical damping.
//
// For a potential U that is convex along the step (here: a spring that stays
// stretched along one line, plus gravity, which is linear), backward Euler
//   m (v' - v) = -h grad U(x'),   x' - x = h v'
// satisfies, by convexity U(x) >= U(x') + grad U(x').(x - x'),
//   U(x) - U(x') >= -grad U(x').(h v') = m (v' - v).v'
//                 = m/2 |v'|^2 - m/2 |v|^2 + m/2 |v' - v|^2,
// so E' <= E - m/2 |v' - v|^2: the total energy E = m|v|^2/2 + U never grows.
// XPBD's prediction + one exact projection of the linear 1-D spring is that
// scheme (the gravity gradient is constant, so explicit = implicit).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

struct EnergyRun {
  std::vector<Real> e;  // J, after every step
};

// Anchor (kinematic) at the origin, particle of mass 1 kg on a spring of rest
// 1 m, alpha = 1e-3 m/N along `axis`, starting at u0 = 0.5 m stretch, with
// gravity g (m/s^2). Energy: m|v|^2/2 + C^2/(2 alpha) - m g.x.
EnergyRun run(const Vec3& axis, const Vec3& g, int substeps, int steps) {
  test::Spring1D sp;
  sp.mat = Material{Real(1e-3), 0, 1};
  SceneDesc sd;
  sd.add_particle(Vec3::Zero(), 0);
  sd.add_particle((sp.rest + sp.u0) * axis, sp.m);
  sd.distances.push_back(DistanceDesc{0, 1, sp.rest, sp.mat});
  const Model m = compile(sd);
  State s = make_state(m);
  StepConfig cfg;
  cfg.substeps = substeps;
  cfg.iterations = 1;
  cfg.gravity = g;
  EnergyRun r;
  auto energy = [&] {
    const Real C = (s.x[1] - s.x[0]).norm() - sp.rest;
    return kinetic_energy(m, s) + C * C / (2 * sp.mat.compliance) + gravity_potential(m, s, g);
  };
  r.e.push_back(energy());
  for (int n = 0; n < steps; ++n) {
    step(m, s, cfg);
    r.e.push_back(energy());
  }
  return r;
}

// Hanging vertical spring under gravity (stays stretched: equilibrium stretch
// m g alpha = 9.8 mm, amplitude 0.49 m < 1 m rest, so the length stays
// positive and the motion stays on the vertical line), default-like settings
// (60 Hz, 10 substeps, 1 iteration): the total energy never grows. Round-off
// of E: a few eps times the largest term (~125 J).
TEST(Energy, HangingSpringNeverGainsEnergy) {
  const Vec3 g(0, Real(-9.81), 0);
  const EnergyRun r = run(-Vec3::UnitY(), g, 10, 300);
  const Real tol = 64 * kEps * 125;
  for (std::size_t n = 1; n < r.e.size(); ++n)
    ASSERT_LE(r.e[n], r.e[n - 1] + tol) << "step " << n << ": " << r.e[n] - r.e[n - 1] << " J";
  // And it does lose energy (numerical damping): the energy above the static
  // equilibrium (stretch u_s = m g alpha, at rest) drops by more than 10%
  // over 5 s (the prediction exp(-w^2 h t) of the next test gives ~100%).
  const Real us = Real(9.81) * Real(1e-3);
  const Real e_min = us * us / (2 * Real(1e-3)) - Real(9.81) * (1 + us);
  EXPECT_LT(r.e.back() - e_min, Real(0.9) * (r.e.front() - e_min));
  std::printf("hanging spring: E0 - Emin = %.6f J, after 5 s %.6g J\n",
              double(r.e.front() - e_min), double(r.e.back() - e_min));
}

// How much is lost, and how substeps shrink it. For the linear spring the
// backward-Euler step map has eigenvalues of modulus 1/sqrt(1 + w^2 h^2), so
// the energy decays like (1 + w^2 h^2)^(-t/h) ~ exp(-w^2 h t): log(E/E0) is
// proportional to h. Four times more substeps (h/4) must lose four times less
// in log terms; the ratio is 4 up to O(w h) oscillation of the non-normal
// step map, so it must lie in [3.5, 4.5]. Compared at whole periods.
TEST(Energy, NumericalDampingShrinksLinearlyWithSubstep) {
  const Vec3 axis = Vec3(1, 2, 2) / Real(3);  // any direction, zero gravity
  const double w = 1 / std::sqrt(1e-3), T = 2 * 3.141592653589793 / w;
  const int steps = int(std::lround(3 * T * 60));  // ~3 periods at 60 Hz
  const EnergyRun coarse = run(axis, Vec3::Zero(), 10, steps);
  const EnergyRun fine = run(axis, Vec3::Zero(), 40, steps);
  for (std::size_t n = 1; n < fine.e.size(); ++n) {
    ASSERT_LE(coarse.e[n], coarse.e[n - 1] * (1 + 64 * kEps)) << "step " << n;
    ASSERT_LE(fine.e[n], fine.e[n - 1] * (1 + 64 * kEps)) << "step " << n;
  }
  const double lc = std::log(double(coarse.e.back() / coarse.e.front()));
  const double lf = std::log(double(fine.e.back() / fine.e.front()));
  const double t = steps / 60.0;
  std::printf("spring energy after %.3f s: %.4f%% left at 10 substeps (predicted %.4f%%), "
              "%.4f%% at 40 (predicted %.4f%%)\n",
              t, 100 * std::exp(lc), 100 * std::exp(-w * w * t / 600),
              100 * std::exp(lf), 100 * std::exp(-w * w * t / 2400));
  EXPECT_GT(lc / lf, 3.5);
  EXPECT_LT(lc / lf, 4.5);
  // And each against the prediction exp(-w^2 h t), within 10%.
  EXPECT_NEAR(lc, -w * w * t / 600, 0.1 * w * w * t / 600);
  EXPECT_NEAR(lf, -w * w * t / 2400, 0.1 * w * w * t / 2400);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
