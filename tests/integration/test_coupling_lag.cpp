// Pre-solve coupling has no lag (docs/bullet-bridge.md, section 2): a body
// coupled to XPBD inside a Bullet world moves as the same body solved by
// XPBD at the substep, whatever the Bullet rate, and Bullet's own contacts
// see it. Measured against closed forms.
//
// Probe: a 1 kg box hanging from a kinematic particle by a compliant
// attachment (XpbdWorld::attach with compliance alpha): a linear spring of
// stiffness k = 1/alpha, rest length 0, omega = 1/sqrt(M alpha). With the
// anchor at the origin, the motion is vertical, and one XPBD substep of h
// with gravity g is exactly
//   v -= g h,  x' = c (x + h v),  v' = (x' - x)/h,  c = 1/(1 + omega^2 h^2)
// (gravity into the velocity, then backward Euler of the spring). The tests
// iterate that map; nothing is taken from the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

struct Hanging {
  std::vector<Real> y, v;  // m, m/s at every Bullet step end
};

// Bullet at `rate` Hz with `substeps` XPBD substeps; the box starts at height
// y0 with vertical velocity v0; Bullet's linear damping `damping`.
Hanging run_bridge(int rate, int substeps, Real alpha, Real y0, Real v0, Real seconds, Real damping = 0) {
  BulletWorld bw;
  const Real dt = Real(1) / Real(rate);
  const Real a = Real(0.05);
  btRigidBody* box = bw.add_body(new btBoxShape(btVector3(a, a, a)), 1, BulletWorld::at(Vec3(0, y0, 0)),
                                 Vec3(0, v0, 0));
  box->setDamping(damping, 0);
  XpbdWorld xw(bw.world());
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3::Zero(), 0);  // kinematic anchor at the origin
  System sys = make_system(scene);
  SystemSettings set;
  set.substeps = substeps;
  set.contacts.enabled = false;
  const auto id = xw.add_system(sys.model, sys.state, set);
  xw.attach(id, 0, box, btVector3(0, 0, 0), alpha);
  Hanging out;
  const int steps = static_cast<int>(std::lround(seconds / dt));
  for (int k = 0; k < steps; ++k) {
    bw.step(dt);
    out.y.push_back(box->getCenterOfMassPosition().y());
    out.v.push_back(box->getLinearVelocity().y());
  }
  return out;
}

// The closed-form map above, sampled every `n` substeps of h; `keep` scales
// the velocity at the start of every sample interval (Bullet's damping
// (1 - d)^dt, applied once per Bullet step).
Hanging closed_form(Real omega, Real h, int n, Real y0, Real v0, int samples, Real keep = 1) {
  const Real c = 1 / (1 + omega * omega * h * h);
  Real y = y0, v = v0;
  Hanging out;
  for (int k = 0; k < samples; ++k) {
    v *= keep;
    for (int i = 0; i < n; ++i) {
      v -= kG * h;
      const Real y1 = c * (y + h * v);
      v = (y1 - y) / h;
      y = y1;
    }
    out.y.push_back(y);
    out.v.push_back(v);
  }
  return out;
}

// Largest |a - b| over the samples.
Real largest_difference(const std::vector<Real>& a, const std::vector<Real>& b) {
  Real d = 0;
  for (std::size_t k = 0; k < a.size(); ++k) d = std::max(d, std::abs(a[k] - b[k]));
  return d;
}

// Round-off allowance (m) for a run of `steps` steps with ~1 cm of motion:
// 1000 ulp of 1 cm per step (2.6e-12 m over 1200 steps in double). A lag of
// the old coupling is 0.2 mm and more (docs/bullet-bridge.md).
Real roundoff(std::size_t steps) { return Real(1000) * Real(steps) * kEps * Real(0.01); }

constexpr Real kAlpha = Real(1e-3);  // m/N: k = 1000 N/m
const Real kOmega = 1 / std::sqrt(1 * kAlpha);  // rad/s, 31.6 (period 0.199 s)

// At one substep per Bullet step the coupling is trivially exact; at 60 Hz
// x 10 substeps it must be exactly as exact: the body follows the substep
// map at h = 1/600 s, sampled every 10 substeps. (The action-hook coupling
// was 2.3 mm off here: gravity arrived once per 1/60 s.)
TEST(CouplingLag, CoupledBodyFollowsTheSubstepMapAtAnyBulletRate) {
  for (const auto& [rate, n] : {std::pair{600, 1}, std::pair{60, 10}, std::pair{120, 5}}) {
    const Real h = Real(1) / Real(rate * n);
    const Hanging b = run_bridge(rate, n, kAlpha, 0, 0, 2);
    const Hanging x = closed_form(kOmega, h, n, 0, 0, static_cast<int>(b.y.size()));
    const Real dy = largest_difference(b.y, x.y), dv = largest_difference(b.v, x.v);
    std::printf("%d Hz x %d vs the substep map at h = 1/600 s: largest difference %.3g m, %.3g m/s over %zu steps\n",
                rate, n, dy, dv, b.y.size());
    EXPECT_LT(dy, roundoff(b.y.size())) << rate << " Hz x " << n;
    // The velocity is a difference quotient (x' - x)/h: its round-off is that over h.
    EXPECT_LT(dv, roundoff(b.y.size()) / h) << rate << " Hz x " << n;
  }
}

// A body resting on the spring is at rest: at the all-XPBD equilibrium
// y = -M g alpha with zero velocity at every step end. (The action hook left
// it on an orbit 0.226 mm higher, reporting +0.0734 m/s while not moving.)
TEST(CouplingLag, RestingBodyIsAtTheEquilibriumWithZeroVelocity) {
  const Real y_eq = -kG * kAlpha;
  const Hanging b = run_bridge(60, 10, kAlpha, y_eq, 0, 2);
  Real dy = 0, v = 0;
  for (std::size_t k = 0; k < b.y.size(); ++k) {
    dy = std::max(dy, std::abs(b.y[k] - y_eq));
    v = std::max(v, std::abs(b.v[k]));
  }
  std::printf("60 Hz x 10 at rest: largest offset from -M g alpha %.3g m, largest |v| %.3g m/s\n", dy, v);
  EXPECT_LT(dy, roundoff(b.y.size()));
  EXPECT_LT(v, roundoff(b.y.size()) * 600);
}

// Bullet's damping does not eat the handed-over velocity: with linear
// damping d, Bullet keeps (1 - d)^dt of the velocity once per step, and the
// coupled body must follow the substep map with exactly that factor applied
// at the start of every Bullet step (the pre-solve prototype, which handed
// the change over as a plain impulse, left 0.3-0.4 mm of penetration).
TEST(CouplingLag, DampedBodyFollowsTheSubstepMapWithBulletsDampingPerStep) {
  const Real d = Real(0.3), dt = Real(1) / 60;
  const Hanging b = run_bridge(60, 10, kAlpha, 0, Real(0.5), 2, d);
  const Hanging x = closed_form(kOmega, dt / 10, 10, 0, Real(0.5), static_cast<int>(b.y.size()),
                                std::pow(1 - d, dt));
  const Real dy = largest_difference(b.y, x.y);
  std::printf("60 Hz x 10, damping %.2g: largest difference to the damped substep map %.3g m\n", double(d), dy);
  EXPECT_LT(dy, roundoff(b.y.size()));
  // Sanity: damping changed the motion by far more than that.
  const Hanging undamped = closed_form(kOmega, dt / 10, 10, 0, Real(0.5), static_cast<int>(b.y.size()));
  EXPECT_GT(largest_difference(undamped.y, x.y), Real(1e-3));
}

// Boxes stacked on a coupled box stay on it: Bullet's solver sees the
// coupled box's XPBD support before it solves the box-box contacts, and the
// box's shadow is given the support Bullet's contacts needed in the previous
// step; in its first coupled step, the support Bullet's solver gives it
// held fixed (the probe, world_probe.cpp). A tray A (1 kg, half extents 2a x a/2 x 2a) hangs from four compliant
// attachments at its top corners (four kinematic particles right above
// them); three 1 kg cubes of half extent a stand on it. Everything starts at
// the static equilibrium (the springs carry 4 m g), each cube 1 um into the
// one below: Bullet's box-box detector reports no contact for boxes that
// exactly touch, so they would fall g dt^2 into each other in the first step.
// Control: the same stack on the tray made static, plain Bullet (its own
// stacking noise). With `beside`, a plain Bullet stack of three cubes on a
// static floor 10 m away, whose end poses are returned: the probe solves
// every manifold of the world once and must put all of it back.
struct StackRun {
  Real vertical = 0;  // m, largest |y - rest| of any box over 10 s
  Real gap = 0;       // m, largest |gap| between neighbours over 10 s
  Real mean_gap = 0;  // m, mean gap between neighbours over the last 5 s
  std::vector<btTransform> beside;  // the plain stack's end poses
};

StackRun run_stack(Real a, bool coupled, bool beside = false, int seconds = 10, int bullet_iterations = 10) {
  BulletWorld bw;
  bw.world().getSolverInfo().m_numIterations = bullet_iterations;
  // The plain stack first, so that its bodies and pairs come in the same
  // order with and without the coupled one.
  std::vector<btRigidBody*> plain;
  if (beside) {
    bw.add_body(new btBoxShape(btVector3(1, Real(0.1), 1)), 0, BulletWorld::at(Vec3(10, -Real(0.1), 0)));
    for (int k = 0; k < 3; ++k)
      plain.push_back(bw.add_body(new btBoxShape(btVector3(a, a, a)), 1,
                                  BulletWorld::at(Vec3(10, (2 * k + 1) * a - Real(1e-6) * (k + 1), 0))));
  }
  const Real alpha = Real(4e-3) * a / Real(0.2);  // m/N per spring
  const int cubes = 3;
  const Real top = -(cubes + 1) * kG * alpha / 4;  // the tray's top face at equilibrium
  std::vector<btRigidBody*> stack;
  std::vector<Real> rest;
  rest.push_back(top - a / 2);
  stack.push_back(bw.add_body(new btBoxShape(btVector3(2 * a, a / 2, 2 * a)), coupled ? 1 : 0,
                              BulletWorld::at(Vec3(0, rest.back(), 0))));
  for (int k = 0; k < cubes; ++k) {
    rest.push_back(top + (2 * k + 1) * a - Real(1e-6) * (k + 1));
    stack.push_back(bw.add_body(new btBoxShape(btVector3(a, a, a)), 1, BulletWorld::at(Vec3(0, rest.back(), 0))));
  }
  XpbdWorld xw(bw.world());
  xpbd::SceneDesc scene;
  for (int i = 0; i < 4; ++i) scene.add_particle(Vec3((i & 1) ? 2 * a : -2 * a, 0, (i & 2) ? 2 * a : -2 * a), 0);
  System sys = make_system(scene);
  SystemSettings set;
  set.contacts.enabled = false;
  const auto id = xw.add_system(sys.model, sys.state, set);
  if (coupled)
    for (int i = 0; i < 4; ++i)
      xw.attach(id, i, stack[0], btVector3((i & 1) ? 2 * a : -2 * a, a / 2, (i & 2) ? 2 * a : -2 * a), alpha);
  StackRun r;
  int samples = 0;
  for (int k = 0; k < seconds * 60; ++k) {
    bw.step();
    for (std::size_t b = 0; b < stack.size(); ++b) {
      const Real y = stack[b]->getCenterOfMassPosition().y();
      r.vertical = std::max(r.vertical, std::abs(y - rest[b]));
      if (b == 0) continue;
      const Real below = b == 1 ? a / 2 : a;
      const Real gap = y - stack[b - 1]->getCenterOfMassPosition().y() - below - a;
      r.gap = std::max(r.gap, std::abs(gap));
      if (k >= 300) r.mean_gap += gap, ++samples;
    }
  }
  r.mean_gap /= Real(samples);
  for (const btRigidBody* b : plain) r.beside.push_back(b->getCenterOfMassTransform());
  return r;
}

// Measured (printed): no sink (mean gap 9-12 um; the action hook sank the
// box on A by 15 mm at 60 Hz), gaps within 0.2 mm of plain Bullet's own.
// Without the probe the tray's shadow knew nothing of the cubes in the first
// step, rose 4 mm in XPBD's substeps, and the stack rang on the springs for
// the whole run: 1.06 and 0.97 mm.
//
// The ring that is left is the stack's own settling: Bullet's solver
// leaves its box-box contacts soft in the first step, and on a tray that
// can move that starts the ring. At Bullet's default 10 iterations its
// largest amplitude is chaotic: with the initial 1 um embeds scaled by
// seven factors from 0.8 to 1.3, 1 among them (a = 0.1, 2026-11-29), it ranged over
// 0.16-0.69 mm before the gyroscopic change of that day and 0.45-1.47 mm
// after it, 0.42 and 0.52 mm unscaled, where plain Bullet on a static tray
// keeps 0.36 mm. At 30 iterations the same seven runs stay within
// 0.070-0.071 mm (0.071-0.117 after the change). So the bound of 0.5 mm
// is asserted at 30 iterations, where it measures the coupling, and so is
// the bound on the gaps (at 10 iterations the float build's largest gap
// went from within it to 0.98 mm with that change). At Bullet's defaults
// the absence of a sink is asserted and the rest printed.
class CouplingLagStack : public ::testing::TestWithParam<Real> {};

TEST_P(CouplingLagStack, BoxesStackedOnCoupledBoxStayOnIt) {
  const Real a = GetParam();
  const StackRun c = run_stack(a, true, false, 10, 30), control = run_stack(a, false, false, 10, 30);
  const StackRun c10 = run_stack(a, true), control10 = run_stack(a, false);
  std::printf("cubes of half extent %.3g m over 10 s, coupled tray (static tray, plain Bullet), Bullet at 30 "
              "iterations: largest vertical distance from rest %.3g m (%.3g), largest |gap| %.3g m (%.3g), mean gap "
              "over the last 5 s %.3g m (%.3g); at Bullet's default 10: %.3g m (%.3g), %.3g m (%.3g), %.3g m (%.3g)\n",
              double(a), double(c.vertical), double(control.vertical), double(c.gap), double(control.gap),
              double(c.mean_gap), double(control.mean_gap), double(c10.vertical), double(control10.vertical),
              double(c10.gap), double(control10.gap), double(c10.mean_gap), double(control10.mean_gap));
  EXPECT_LT(std::abs(c.mean_gap), Real(1e-4));       // no sink
  EXPECT_LT(std::abs(c10.mean_gap), Real(1e-4));     // no sink at Bullet's defaults either
  EXPECT_LT(c.gap, control.gap + Real(5e-4));        // gaps as Bullet's own, within 0.5 mm
  EXPECT_LT(c.vertical, Real(5e-4));                  // every box within 0.5 mm of rest
}

// The probe runs Bullet's solver over the whole world once and puts back
// what it wrote: a plain Bullet stack next to the coupled one ends, after
// 2 s, bit for bit where it ends in the same world without a coupled one.
TEST(CouplingLag, ProbeLeavesTheRestOfTheWorldAsItWas) {
  const StackRun with = run_stack(Real(0.1), true, true, 2);
  // The same world without the XpbdWorld: the tray static, no springs.
  const StackRun without = run_stack(Real(0.1), false, true, 2);
  ASSERT_EQ(with.beside.size(), std::size_t(3));
  ASSERT_EQ(without.beside.size(), std::size_t(3));
  for (std::size_t b = 0; b < 3; ++b) {
    EXPECT_EQ(with.beside[b].getOrigin(), without.beside[b].getOrigin()) << "cube " << b;
    EXPECT_EQ(with.beside[b].getRotation(), without.beside[b].getRotation()) << "cube " << b;
  }
  // Sanity: the plain stack moved (settled) in that time.
  EXPECT_NE(without.beside[2].getOrigin().y(), (2 * 2 + 1) * Real(0.1) - Real(3e-6));
}

INSTANTIATE_TEST_SUITE_P(BoxSizes, CouplingLagStack, ::testing::Values(Real(0.1), Real(0.2)));

// The same comparison with rotation, against an independent all-XPBD run: a
// box (1 kg, half extents 0.1 x 0.05 x 0.2 m) hangs from two compliant
// attachments at two of its corners, released tilted and moving, so it
// swings and spins. Reference: the same box as an xpbd::RigidBody in
// xpbd::step (gravity as RigidBody::accel, the attachments as
// BodyAttachment to two kinematic particles), at the same substep. The
// bridge runs Bullet at 60 Hz with 10 XPBD substeps; the reference runs
// xpbd::step at dt = 1/60 with 10 substeps. Bullet's integration of the
// box is replaced by the residual, so the two must agree to round-off.
TEST(CouplingLag, SwingingBoxMatchesTheSameBodySolvedByXpbd) {
  const Vec3 half(0.1, 0.05, 0.2);
  const Real mass = 1, alpha = Real(2e-3);
  const Vec3 x0(0.05, -0.3, 0.02), v0(0.3, 0, -0.2), w0(1, -0.5, 2);
  const xpbd::Quat q0(Eigen::AngleAxis<Real>(Real(0.3), Vec3(1, 2, 3).normalized()));
  const Vec3 corners[2] = {Vec3(half.x(), half.y(), half.z()), Vec3(-half.x(), half.y(), -half.z())};
  const Vec3 anchors[2] = {Vec3(0.15, 0, 0.2), Vec3(-0.1, 0, -0.2)};
  const int steps = 120, n = 10;

  // Bridge.
  BulletWorld bw;
  btTransform pose(btQuaternion(q0.x(), q0.y(), q0.z(), q0.w()), bt(x0));
  btRigidBody* box = bw.add_body(new btBoxShape(bt(half)), mass, pose, v0);
  box->setAngularVelocity(bt(w0));
  // Bullet's gyroscopic flag stays on (its default): the bridge turns it off
  // for the steps that couple the box, whose substeps integrate that term
  // themselves, as xpbd::step does for the reference below, and puts it
  // back after each step. (Left on in Bullet's step, the box was up to
  // 0.14 m and 3.1 rad away from the reference within the 2 s, measured.)
  const int flags = box->getFlags();
  ASSERT_NE(flags & BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY, 0);
  XpbdWorld xw(bw.world());
  xpbd::SceneDesc scene;
  for (const Vec3& a : anchors) scene.add_particle(a, 0);
  System sys = make_system(scene);
  SystemSettings set;
  set.substeps = n;
  set.contacts.enabled = false;
  const auto id = xw.add_system(sys.model, sys.state, set);
  for (int i = 0; i < 2; ++i) xw.attach(id, i, box, bt(corners[i]), alpha);

  // Reference: the box as an XPBD rigid body.
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  xpbd::RigidBody b;
  b.x = x0;
  b.q = q0;
  b.v = v0;
  b.w = w0;
  b.inv_mass = 1 / mass;
  btVector3 inertia;
  box->getCollisionShape()->calculateLocalInertia(mass, inertia);
  b.inv_inertia = Vec3(1 / inertia.x(), 1 / inertia.y(), 1 / inertia.z());
  b.accel = Vec3(0, -kG, 0);
  xpbd::StepConfig cfg;
  cfg.dt = kDt;
  cfg.substeps = n;
  cfg.gravity = Vec3(0, -kG, 0);
  Real dx = 0, dq = 0, travel = 0, turned = 0;
  for (int k = 0; k < steps; ++k) {
    // The host rebuilds bodies and attachments every step, as the bridge does.
    s.bodies.assign(1, b);
    s.attachments.clear();
    for (int i = 0; i < 2; ++i) s.attachments.push_back(xpbd::BodyAttachment{Index(i), 0, corners[i], alpha});
    xpbd::step(m, s, cfg);
    b = s.bodies[0];
    b.accel = Vec3(0, -kG, 0);
    bw.step();
    ASSERT_EQ(box->getFlags(), flags) << "step " << k;
    const btTransform t = box->getCenterOfMassTransform();
    const btQuaternion r = t.getRotation();
    const xpbd::Quat qb(r.w(), r.x(), r.y(), r.z());
    dx = std::max(dx, (vec(t.getOrigin()) - b.x).norm());
    dq = std::max(dq, Real(2) * std::asin(std::min(Real(1), (qb * b.q.conjugate()).vec().norm())));
    travel = std::max(travel, (b.x - x0).norm());
    turned = std::max(turned, Real(2) * std::asin(std::min(Real(1), (b.q * q0.conjugate()).vec().norm())));
  }
  std::printf("swinging box, 60 Hz x 10 vs xpbd::step with a rigid body: largest position difference %.3g m "
              "(it travelled up to %.3g m), largest rotation difference %.3g rad (it turned up to %.3g rad)\n",
              double(dx), double(travel), double(dq), double(turned));
  // Sanity: it really moved and turned.
  EXPECT_GT(travel, Real(0.05));
  EXPECT_GT(turned, Real(0.5));
  // Round-off: the two runs associate the same arithmetic differently
  // (Bullet's transform round trips, its quaternion integration followed by
  // the residual); 1e6 ulp of the motion over 120 steps.
  EXPECT_LT(dx, Real(1e6) * kEps * travel);
  EXPECT_LT(dq, Real(1e6) * kEps * turned);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
