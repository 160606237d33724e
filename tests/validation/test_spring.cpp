// Compliant spring, alpha = 1/k (docs/design.md section 6, row 2).
//
// Scene (test::Spring1D): m = 1 kg, rest 1 m, x0 = 1.5 m (u0 = x0 - rest =
// 0.5 m), alpha = 1e-3 m/N, the other end kinematic, zero gravity. The motion
// stays on the x axis and the constraint is linear in u = x - rest.
//
// Converged XPBD with one substep h is backward Euler for u'' = -w^2 u,
// w = 1/sqrt(m alpha):
//   u_{n+1} = u_n + h v_{n+1},   v_{n+1} = v_n - h w^2 u_{n+1}.
// In matrix form [[1, -h], [h w^2, 1]] (u, v)_{n+1} = (u, v)_n; that matrix
// has eigenvalues 1 +- i h w, so the step map has eigenvalues
// r e^{-+i phi} with
//   r = 1/sqrt(1 + w^2 h^2)   (amplitude factor per step)
//   phi = atan(w h)           (phase per step).
// Hence u_n = r^n (c1 cos(n phi) + c2 sin(n phi)). From the initial
// conditions: c1 = u0; and u_1 = (u0 + h v0)/(1 + w^2 h^2) = r^2 (u0 + h v0)
// must equal r (u0 cos phi + c2 sin phi). With cos phi = r and
// sin phi = w h r this gives c2 = v0 / w. So, derived and not fitted:
//   u_n = r^n (u0 cos(n phi) + (v0/w) sin(n phi)) = A r^n cos(n phi + phi0),
//   A = sqrt(u0^2 + (v0/w)^2),  phi0 = -atan2(v0/w, u0).
// The discrete period is 2 pi h / atan(w h) -> 2 pi / w = 2 pi sqrt(m alpha)
// as h -> 0, with relative error (w h)^2/3 + O(h^4).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

constexpr double kPi = std::numbers::pi;

struct Trajectory {
  std::vector<double> t, u;
};

// Runs the spring with one substep of h and `iterations` iterations.
Trajectory run(const test::Spring1D& sp, double h, int steps, int iterations) {
  const Model m = compile(test::spring_scene(sp));
  State s = make_state(m);
  StepConfig cfg;
  cfg.dt = Real(h);
  cfg.substeps = 1;
  cfg.iterations = iterations;
  cfg.gravity.setZero();
  Trajectory tr;
  tr.t.push_back(0);
  tr.u.push_back(double(s.x[1].x() - sp.rest));
  for (int n = 1; n <= steps; ++n) {
    step(m, s, cfg);
    tr.t.push_back(n * h);
    tr.u.push_back(double(s.x[1].x() - sp.rest));
  }
  return tr;
}

test::Spring1D design_spring(double v0) {
  test::Spring1D sp;
  sp.m = 1;
  sp.rest = 1;
  sp.u0 = Real(0.5);
  sp.v0 = Real(v0);
  sp.mat = Material{Real(1e-3), 0, 1};
  return sp;
}

// The trajectory matches the closed-form discrete solution at every step, to
// 1e-6 of the current envelope A r^n. Over 1000 steps that bounds the error
// of the amplitude factor per step to ~1e-9 relative and of the phase per step
// to ~1e-9 rad (an error d in either accumulates to about n d).
TEST(Spring, ConvergedXpbdIsBackwardEuler) {
  for (double v0 : {0.0, 3.0}) {  // m/s; with and without initial velocity
    const test::Spring1D sp = design_spring(v0);
    const double h = 2e-3;  // s: w h = 0.063, r = 0.998, about 100 steps per period
    const int steps = 1000;
    const Trajectory tr = run(sp, h, steps, 20);
    const double w = 1 / std::sqrt(double(sp.m) * double(sp.mat.compliance));
    const double r = 1 / std::sqrt(1 + w * w * h * h);
    const double phi = std::atan(w * h);
    const double u0 = double(sp.u0), c2 = v0 / w;
    const double A = std::sqrt(u0 * u0 + c2 * c2), phi0 = -std::atan2(c2, u0);
    double worst = 0;
    for (int n = 0; n <= steps; ++n) {
      const double env = A * std::pow(r, n);
      const double ref = env * std::cos(n * phi + phi0);
      const double err = std::abs(tr.u[std::size_t(n)] - ref) / env;
      ASSERT_LT(err, 1e-6) << "v0 " << v0 << " step " << n << " u " << tr.u[std::size_t(n)]
                           << " ref " << ref;
      worst = std::max(worst, err);
    }
    std::printf("spring v0=%g: r=%.9f/step phi=%.9f rad/step, max |u-ref|/envelope = %.3g\n", v0,
                r, phi, worst);
  }
}

// As h -> 0 the measured period approaches the continuous 2 pi sqrt(m alpha).
// For each h the period measured from zero crossings must match the discrete
// prediction 2 pi h/atan(w h). Tolerance: linear interpolation between
// samples misplaces a crossing by at most ~(w h)^2 h/8 (the curvature of
// r^n cos(n phi) at a zero comes from the decay, |ln r| ~ (w h)^2/2 per step,
// plus the cubic term of the cosine, of the same order), so the period from
// two crossings a time `span` apart is off by at most (w h)^2 h/(4 span);
// the test allows (w h)^2 h/span. The error with respect to the continuous
// period must shrink like h^2: by a factor in [3.5, 4.5] per halving of h
// (the leading term (w h)^2/3 gives 4, the next -4(w h)^4/45 shifts it by
// < 2% at these h).
TEST(Spring, PeriodApproachesContinuousAsStepShrinks) {
  const test::Spring1D sp = design_spring(0);
  const double w = 1 / std::sqrt(double(sp.m) * double(sp.mat.compliance));
  const double T_cont = 2 * kPi / w;  // 0.19869 s
  double prev_err = 0;
  for (double h : {8e-3, 4e-3, 2e-3, 1e-3}) {
    const int steps = int(std::lround(1.0 / h));  // 1 s, about 5 periods
    const Trajectory tr = run(sp, h, steps, 20);
    const auto crossings = test::zero_crossings(tr.t, tr.u, +1);
    ASSERT_GE(crossings.size(), 4u);
    const double T = test::mean_period(crossings);
    const double span = crossings.back() - crossings.front();
    const double T_disc = 2 * kPi * h / std::atan(w * h);
    const double err = std::abs(T - T_cont) / T_cont;
    std::printf("spring h=%g: T=%.9f s, discrete %.9f s, continuous %.9f s, rel err %.3g\n", h, T,
                T_disc, T_cont, err);
    EXPECT_NEAR(T / T_disc, 1, (w * h) * (w * h) * h / span) << "h " << h;
    EXPECT_NEAR(err, (w * h) * (w * h) / 3, 0.1 * (w * h) * (w * h) / 3) << "h " << h;
    if (prev_err > 0) {
      EXPECT_GT(prev_err / err, 3.5) << "h " << h;
      EXPECT_LT(prev_err / err, 4.5) << "h " << h;
    }
    prev_err = err;
  }
  EXPECT_LT(prev_err, 4e-4);  // at h = 1 ms: (w h)^2/3 = 3.3e-4
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
