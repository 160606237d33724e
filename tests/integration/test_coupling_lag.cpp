// The coupling lag of XpbdWorld's hook (a btActionInterface: Bullet applies
// gravity and solves its own contacts for the whole internal step before
// XPBD runs; docs/bullet-bridge.md), measured against closed forms.
//
// Probe: a 1 kg box hanging from a kinematic particle by a compliant
// attachment (XpbdWorld::attach with compliance alpha): a linear spring of
// stiffness k = 1/alpha, rest length 0, omega = 1/sqrt(M alpha). With the
// anchor at the origin, the motion is vertical, so the XPBD attachment
// projection is exactly linear: one substep of h maps
//   x' = c (x + h v),  v' = (x' - x)/h,  c = 1/(1 + omega^2 h^2)
// (backward Euler of the spring). In an all-XPBD scene gravity enters each
// substep (v -= g h before the move); in the bridge Bullet adds the whole
// step's g dt to the velocity once, and the shadow body then runs the n
// substeps without gravity. Both are written out below and give the
// expected values; nothing is taken from the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "support.hpp"

namespace {

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

using Vec2 = Eigen::Matrix<Real, 2, 1>;
using Mat2 = Eigen::Matrix<Real, 2, 2>;

// One backward-Euler substep of the spring on (x, v), without gravity.
Mat2 substep_map(Real omega, Real h) {
  const Real c = 1 / (1 + omega * omega * h * h);
  Mat2 S;
  S << c, c * h, (c - 1) / h, c;
  return S;
}

// The bridge's map over one Bullet step of dt = n h: v -= g dt, then n substeps.
// Its fixed point z = S^n (z - (0, g dt)) is the state a resting body returns
// to at every step end.
Vec2 bridge_fixed_point(Real omega, Real dt, int n) {
  Mat2 Sn = Mat2::Identity();
  const Mat2 S = substep_map(omega, dt / n);
  for (int i = 0; i < n; ++i) Sn = S * Sn;
  const Vec2 kick(0, kG * dt);
  return -(Mat2::Identity() - Sn).inverse() * Sn * kick;
}

struct Hanging {
  std::vector<Real> t, y, v;  // s, m, m/s at every Bullet step end
};

// Bridge run: Bullet at `rate` Hz with `substeps` XPBD substeps; the box
// starts at height y0 with vertical velocity v0.
Hanging run_bridge(int rate, int substeps, Real alpha, Real y0, Real v0, Real seconds) {
  BulletWorld bw;
  const Real dt = Real(1) / Real(rate);
  const Real a = Real(0.05);
  btRigidBody* box = bw.add_body(new btBoxShape(btVector3(a, a, a)), 1, BulletWorld::at(Vec3(0, y0, 0)),
                                 Vec3(0, v0, 0));
  XpbdWorld xw(bw.world());
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3::Zero(), 0);  // kinematic anchor at the origin
  System sys = make_system(scene);
  SystemSettings set;
  set.substeps = substeps;
  set.contacts.enabled = false;
  const int id = xw.add_system(sys.model, sys.state, set);
  xw.attach(id, 0, box, btVector3(0, 0, 0), alpha);
  Hanging out;
  const int steps = static_cast<int>(std::lround(seconds / dt));
  for (int k = 0; k < steps; ++k) {
    bw.step(dt);
    out.t.push_back(Real(k + 1) * dt);
    out.y.push_back(box->getCenterOfMassPosition().y());
    out.v.push_back(box->getLinearVelocity().y());
  }
  return out;
}

// All-XPBD run of the same spring (no Bullet): anchor (mass 0) at the
// origin, a 1 kg particle joined to it by a distance constraint of rest
// length 1 m hanging below it (so |x| > 0 always and the gradient is the
// vertical). Gravity is applied every substep. Heights are returned
// relative to the rest length, to compare with the attachment's rest length 0.
Hanging run_all_xpbd(Real h, Real alpha, Real y0, Real v0, Real seconds) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3::Zero(), 0);
  scene.add_particle(Vec3(0, y0 - 1, 0), 1, 0, Vec3(0, v0, 0));
  xpbd::DistanceDesc d;
  d.a = 0;
  d.b = 1;
  d.rest = 1;
  d.mat.compliance = alpha;
  scene.distances.push_back(d);
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  xpbd::StepConfig cfg;
  cfg.dt = h;
  cfg.substeps = 1;
  cfg.gravity = Vec3(0, -kG, 0);
  Hanging out;
  const int steps = static_cast<int>(std::lround(seconds / h));
  for (int k = 0; k < steps; ++k) {
    xpbd::step(m, s, cfg);
    out.t.push_back(Real(k + 1) * h);
    out.y.push_back(s.x[1].y() + 1);
    out.v.push_back(s.v[1].y());
  }
  return out;
}

Real mean_period(const Hanging& r, Real level) {
  const std::vector<Real> up = upward_crossings(r.t, r.y, level);
  return (up.back() - up.front()) / Real(up.size() - 1);
}

// Round-off allowance (m) for a run of `steps` steps with ~1 cm of motion:
// 1000 ulp of 1 cm per step.
Real roundoff(std::size_t steps) { return Real(1000) * Real(steps) * kEps * Real(0.01); }

constexpr Real kAlpha = Real(1e-3);  // m/N: k = 1000 N/m
const Real kOmega = 1 / std::sqrt(1 * kAlpha);  // rad/s, 31.6 (period 0.199 s)

// Coupled once per substep (Bullet at 600 Hz, one XPBD substep), the lumped
// gravity IS per-substep gravity: the bridge must reproduce the all-XPBD
// trajectory. Released at the spring's rest length, at rest.
TEST(CouplingLag, OneSubstepPerBulletStepMatchesAllXpbd) {
  const Hanging b = run_bridge(600, 1, kAlpha, 0, 0, 2);
  const Hanging x = run_all_xpbd(Real(1) / 600, kAlpha, 0, 0, 2);
  Real diff = 0;
  for (std::size_t k = 0; k < b.y.size(); ++k) diff = std::max(diff, std::abs(b.y[k] - x.y[k]));
  std::printf("600 Hz x 1 vs all-XPBD: largest height difference %.3g m over %zu steps\n", diff,
              b.y.size());
  // Same arithmetic up to association (Bullet's transform round trip, the
  // attachment vs distance kernels): a few ulp of the 1 cm amplitude per
  // step, growing at most linearly over the steps (double: ~20 ulp per step
  // observed). 1000 ulp of 1 cm per step is allowed (2.6e-12 m in double);
  // a wrong coupling is off by millimetres.
  EXPECT_LT(diff, roundoff(b.y.size()));
}

// At 60 Hz with 10 substeps, gravity arrives once per 1/60 s. A resting
// body is then not at rest within the step: at every step end it is at the
// fixed point of the bridge's map (see bridge_fixed_point), not at the
// all-XPBD equilibrium (y = -M g alpha, v = 0). For omega dt -> 0 the fixed
// point tends to v = g dt/2 (n-1)/n upward and y = -M g alpha + g dt^2/12:
// this is the lag, measured here.
TEST(CouplingLag, RestingBodyEndsEachStepOnTheLumpedGravityOrbit) {
  const int rate = 60, n = 10;
  const Real dt = Real(1) / rate;
  const Vec2 z = bridge_fixed_point(kOmega, dt, n);
  // Started on the orbit, the body must stay on it.
  const Hanging b = run_bridge(rate, n, kAlpha, z(0), z(1), 2);
  Real dy = 0, dv = 0;
  for (std::size_t k = 0; k < b.y.size(); ++k) {
    dy = std::max(dy, std::abs(b.y[k] - z(0)));
    dv = std::max(dv, std::abs(b.v[k] - z(1)));
  }
  const Real y_eq = -kG * kAlpha;
  std::printf("60 Hz x 10 resting orbit: step-end y %.6g m (all-XPBD equilibrium %.6g, offset %.3g m; "
              "g dt^2/12 = %.3g), step-end v %.5g m/s (g dt/2 = %.4g); largest deviation over 2 s: "
              "%.3g m, %.3g m/s\n",
              z(0), y_eq, z(0) - y_eq, kG * dt * dt / 12, z(1), kG * dt / 2, dy, dv);
  // The fixed point is exact for the discrete scheme; deviations are
  // round-off, bounded as in OneSubstepPerBulletStepMatchesAllXpbd (and, for
  // the velocity (x - x_prev)/h, that divided by h). A wrong scheme drifts off
  // the orbit by millimetres and centimetres per second.
  EXPECT_LT(dy, roundoff(b.y.size()));
  EXPECT_LT(dv, roundoff(b.y.size()) * Real(n) / dt);
  // The lag is real: the orbit is not the all-XPBD rest state.
  EXPECT_GT(z(1), Real(0.5) * kG * dt / 2);
}

// The lumped gravity shifts the orbit, not the oscillation: the bridge's
// step map is z -> S^n (z - kick), so the deviation from its fixed point z*
// evolves by S^n per step, exactly as the all-XPBD deviation from its
// equilibrium evolves by S per substep. Released at the rest length (an
// oscillation of ~1 cm), every step end must equal
//   y_k = z*_0 + [S^(n k) (z_0 - z*)]_0,
// whose period is that of backward Euler at h, 2 pi h / atan(omega h).
TEST(CouplingLag, OscillationIsTheAllXpbdOscillationAboutTheShiftedOrbit) {
  const int rate = 60, n = 10;
  const Real dt = Real(1) / rate, h = dt / n;
  const Vec2 zs = bridge_fixed_point(kOmega, dt, n);
  const Hanging b = run_bridge(rate, n, kAlpha, 0, 0, 2);
  Mat2 Sn = Mat2::Identity();
  for (int i = 0; i < n; ++i) Sn = substep_map(kOmega, h) * Sn;
  Vec2 dev = Vec2(0, 0) - zs;
  Real diff = 0, amp = 0;
  for (std::size_t k = 0; k < b.y.size(); ++k) {
    dev = Sn * dev;
    diff = std::max(diff, std::abs(b.y[k] - (zs(0) + dev(0))));
    amp = std::max(amp, std::abs(dev(0)));
  }
  const Hanging x = run_all_xpbd(h, kAlpha, 0, 0, 2);
  const Real T_be = 2 * kPi * h / std::atan(kOmega * h);
  std::printf("60 Hz x 10 oscillation vs closed form: largest difference %.3g m (amplitude %.3g m); "
              "period: backward Euler %.6g s, all-XPBD measured %.6g s, continuous %.6g s\n",
              diff, amp, T_be, mean_period(x, -kG * kAlpha), 2 * kPi / kOmega);
  // Round-off only (see OneSubstepPerBulletStepMatchesAllXpbd).
  EXPECT_LT(diff, roundoff(b.y.size()));
  // Sanity of the probe: a real oscillation was compared.
  EXPECT_GT(amp, Real(1e-3));
}

// DISABLED: fails with the current coupling (docs/bullet-bridge.md, "Known
// limitations"). Box B (1 kg) rests on box A (1 kg); A hangs from four
// compliant attachments at its top corners (four kinematic particles right
// above them; four springs make the suspension rotationally stable, where a
// single one at A's centre would let the stack topple like an inverted
// pendulum). Each step XpbdWorld moves A to its shadow's pose
// (setCenterOfMassTransform) after Bullet has solved the A-B contact, so B is
// left behind by about g dt^2 per step and Bullet's penetration recovery
// catches up with only a fraction of it per step. Measured: with 0.4 m boxes
// B sits 15 mm inside A at 60 Hz x 10 substeps (4 mm at 120 Hz, 1 mm at
// 240 Hz, 0.3 mm at 600 Hz x 1), against 0.01 mm for the same stack on a
// static floor in plain Bullet; with 0.1 m boxes B is pushed off A within
// 6 s at 60 and 120 Hz. Run with --gtest_also_run_disabled_tests.
class CouplingLagStack : public ::testing::TestWithParam<Real> {};

TEST_P(CouplingLagStack, DISABLED_BoxStackedOnCoupledBoxStaysOnIt) {
  BulletWorld bw;
  const Real a = GetParam(), alpha = Real(4e-3);  // m (half extent), m/N per spring
  // Static equilibrium: the four springs carry 2 m g, each stretched by
  // 2 m g alpha / 4; A's top face hangs that far below y = 0.
  const Real yA = -2 * kG * alpha / 4 - a;
  btRigidBody* A = bw.add_body(new btBoxShape(btVector3(a, a, a)), 1, BulletWorld::at(Vec3(0, yA, 0)));
  btRigidBody* B = bw.add_body(new btBoxShape(btVector3(a, a, a)), 1, BulletWorld::at(Vec3(0, yA + 2 * a, 0)));
  XpbdWorld xw(bw.world());
  xpbd::SceneDesc scene;
  for (int i = 0; i < 4; ++i) scene.add_particle(Vec3((i & 1) ? a : -a, 0, (i & 2) ? a : -a), 0);
  System sys = make_system(scene);
  SystemSettings set;
  set.contacts.enabled = false;
  const int id = xw.add_system(sys.model, sys.state, set);
  for (int i = 0; i < 4; ++i) xw.attach(id, i, A, btVector3((i & 1) ? a : -a, a, (i & 2) ? a : -a), alpha);
  Real worst = 0;
  for (int k = 0; k < 6 * 60; ++k) {
    bw.step();
    worst = std::min(worst, Real(B->getCenterOfMassPosition().y() - A->getCenterOfMassPosition().y() - 2 * a));
  }
  std::printf("half extent %.3g m: lowest (B bottom - A top) %.4g m\n", a, worst);
  // Plain Bullet keeps a resting stack within ~0.01 mm; allow 1 mm.
  EXPECT_GT(worst, Real(-1e-3));
}

INSTANTIATE_TEST_SUITE_P(BoxSizes, CouplingLagStack, ::testing::Values(Real(0.05), Real(0.2)));

}  // namespace
