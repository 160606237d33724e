// A particle attached to one body and pressed or rubbed by another
// (xpbd/src/contact_block.cpp): the attachment joins the particle's joint
// contact solve, so the particle is a spacer between the two bodies, and
// the body that presses on it is held or stopped as if it touched the other
// body directly. Closed forms: rest, momentum, Coulomb's stopping distance.
//
// Solved one after the other, the contact moved the light particle (not
// the heavy body) off its attachment point, and the attachment moved it
// back (not the body it hangs from): the heavy body fell or slid through.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "xpbd/rigid_solve.hpp"
#include "xpbd/xpbd.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;

constexpr Real kT = Real(0.005);      // m, contact thickness
constexpr Real kHalf = Real(0.05);    // m, the pressing body's half height
constexpr Real kG = Real(9.81);       // m/s^2
constexpr Real kParticle = Real(1e-3);  // kg

// A 1 g particle at the origin, and body 0 of mass `mass` whose bottom face
// rests on the particle's band, straight above it, moving at v; the contact
// has friction mu. The particle's attachment is added by each test.
struct Scene {
  xpbd::Model m;
  xpbd::State s;
};
Scene pressed_particle(Real mass, const Vec3& v, Real mu) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3::Zero(), kParticle);
  Scene sc{xpbd::compile(scene), {}};
  sc.s = xpbd::make_state(sc.m);
  xpbd::RigidBody b;
  b.x = Vec3(0, kT + kHalf, 0);
  b.v = v;
  b.inv_mass = 1 / mass;
  b.inv_inertia = Vec3::Constant(Real(6) / (mass * (2 * kHalf) * (2 * kHalf)));  // a cube of side 2 kHalf
  sc.s.bodies.push_back(b);
  xpbd::BodyContact face;  // the body's bottom face, normal -y
  face.particle = 0;
  face.body = 0;
  face.r = Vec3(0, -kHalf, 0);
  face.n = Vec3(0, -1, 0);
  face.thickness = kT;
  face.static_friction = face.dynamic_friction = mu;
  sc.s.contacts = {face};
  return sc;
}

xpbd::BodyAttachment attach(xpbd::Index body, const Vec3& r) {
  xpbd::BodyAttachment a;
  a.particle = 0;
  a.body = body;
  a.r = r;
  return a;
}

// A 100 kg body resting on a particle that is attached to a fixed world
// point: the point holds the body up, at rest, one thickness above it.
// One by one, the body fell almost freely (it is 1e5 times heavier).
TEST(AttachedContacts, HeavyBodyRestsOnAParticleAttachedToAFixedPoint) {
  Scene sc = pressed_particle(100, Vec3::Zero(), 0);
  sc.s.attachments = {attach(-1, Vec3::Zero())};
  xpbd::StepConfig cfg;
  cfg.gravity = Vec3(0, -kG, 0);
  sc.s.bodies[0].accel = cfg.gravity;
  for (int k = 0; k < 60; ++k) xpbd::step(sc.m, sc.s, cfg);
  // At rest the body's weight M g acts through the particle; the
  // attachment is rigid (compliance 0), so only the solve's round-off and
  // the substep's first-order motion remain: far below 0.1 mm.
  EXPECT_NEAR(double(sc.s.bodies[0].x.y()), double(kT + kHalf), 1e-4);
  EXPECT_NEAR(double(sc.s.x[0].norm()), 0.0, 1e-4);
  EXPECT_LT(double(sc.s.bodies[0].v.norm()), 1e-3);
}

// The same on a compliant attachment (alpha = 1e-6 m/N): the particle
// gives under the body's weight by alpha (M + m) g = 0.98 mm, the body rests
// one thickness above it, and the attachment reports the whole weight on
// its fixed point (forces.hpp). The joint block takes the attachment's
// compliance term (alpha/h^2 times its multiplier); without it the particle
// would not give at all.
TEST(AttachedContacts, HeavyBodyOnACompliantAttachmentDeflectsItByItsWeight) {
  const Real M = 100, alpha = Real(1e-6);
  Scene sc = pressed_particle(M, Vec3::Zero(), 0);
  xpbd::BodyAttachment a = attach(-1, Vec3::Zero());
  a.compliance = alpha;
  sc.s.attachments = {a};
  xpbd::StepConfig cfg;
  cfg.gravity = Vec3(0, -kG, 0);
  sc.s.bodies[0].accel = cfg.gravity;
  for (int k = 0; k < 120; ++k) xpbd::step(sc.m, sc.s, cfg);
  const double weight = double((M + kParticle) * kG);  // N
  const double sag = double(alpha) * weight;           // 0.98 mm
  // Settled (the body's oscillation on the spring, period 2 pi sqrt(alpha
  // M) = 63 ms, is damped by the substeps' implicit integration) to 1 %
  // of the deflection.
  EXPECT_NEAR(double(sc.s.x[0].y()), -sag, 0.01 * sag);
  EXPECT_NEAR(double(sc.s.bodies[0].x.y()), double(kT + kHalf) - sag, 0.01 * sag);
  const std::vector<xpbd::AttachmentForce> f = xpbd::attachment_forces(sc.m, sc.s);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_NEAR(double(f[0].on_body.y()), -weight, 0.01 * weight);
  EXPECT_NEAR(double(f[0].on_body.x()), 0.0, 1e-6 * weight);
}

// No gravity: a 100 kg body moving down at 1 m/s hits a particle attached
// to the top of a free 1 kg body. The contact has no restitution, so the
// three move on together at M v / (M + m_A + m_p) (momentum), and the
// pressing body's face stays one thickness above the particle. One by one,
// the light body got the momentum only through the particle's and the
// pressing body passed through the particle.
TEST(AttachedContacts, BodyHittingAnAttachedParticleCarriesItsBodyAlong) {
  const Real M = 100, mA = 1, v0 = 1;
  Scene sc = pressed_particle(M, Vec3(0, -v0, 0), 0);
  sc.s.bodies[0].x.y() += Real(0.01);  // 1 cm above the band: it hits in the first step
  xpbd::RigidBody a;  // the light body, the particle 0.05 m above its centre
  a.x = Vec3(0, -Real(0.05), 0);
  a.inv_mass = 1 / mA;
  a.inv_inertia = Vec3::Constant(Real(6) / (mA * Real(0.01)));
  sc.s.bodies.push_back(a);
  sc.s.attachments = {attach(1, Vec3(0, Real(0.05), 0))};
  xpbd::StepConfig cfg;
  cfg.gravity.setZero();
  for (int k = 0; k < 30; ++k) xpbd::step(sc.m, sc.s, cfg);
  const double v = double(M * v0 / (M + mA + kParticle));
  // Momentum is exchanged exactly (equal and opposite corrections); the
  // velocities are position differences (about 0.5 m) over a substep h:
  // round-off, a few ulps of 1 m over h in the build's scalar (float:
  // 1e-3 m/s). A body that takes the momentum only through the particle
  // is off by O(1).
  const double h = double(cfg.dt) / cfg.substeps;
  const double tol = 1e-6 * v + 16 * double(std::numeric_limits<Real>::epsilon()) / h;
  EXPECT_NEAR(double(sc.s.bodies[0].v.y()), -v, tol);
  EXPECT_NEAR(double(sc.s.bodies[1].v.y()), -v, tol);
  EXPECT_NEAR(double(sc.s.v[0].y()), -v, tol);
  // The face above the particle, by the thickness (a few substeps' first-
  // order rotation error at most: nothing turns here).
  const double gap = double(sc.s.bodies[0].x.y() - kHalf - sc.s.x[0].y());
  EXPECT_NEAR(gap, double(kT), 1e-5);
}

// A 100 kg body (not turning) sliding at 1 m/s on a particle attached to a
// fixed point, friction mu: the point holds the particle, so Coulomb's law between the
// body and the point stops the body after v0^2 / (2 mu g). One by one, the
// body's friction moved only the particle along, the attachment pulled it
// back, and the body slid on (it lost the particle's momentum per substep).
TEST(AttachedContacts, BodySlidingOnAnAttachedParticleStopsAtTheCoulombDistance) {
  const Real v0 = 1, mu = Real(0.4);
  Scene sc = pressed_particle(100, Vec3(v0, 0, 0), mu);
  // Not turning: on a single point of support, friction under the centre
  // would tip a free body over (as it does in the real world).
  sc.s.bodies[0].inv_inertia.setZero();
  sc.s.attachments = {attach(-1, Vec3::Zero())};
  xpbd::StepConfig cfg;
  cfg.gravity = Vec3(0, -kG, 0);
  cfg.substeps = 20;
  sc.s.bodies[0].accel = cfg.gravity;
  for (int k = 0; k < 40; ++k) xpbd::step(sc.m, sc.s, cfg);
  const Real expected = v0 * v0 / (2 * mu * kG);  // 0.127 m, in 0.25 s
  // Discretisation: of the order of a substep's travel, v0 h ~ 0.8 mm.
  EXPECT_NEAR(double(sc.s.bodies[0].x.x()), double(expected), 0.02 * double(expected));
  EXPECT_LT(double(sc.s.bodies[0].v.norm()), 1e-3);
  EXPECT_NEAR(double(sc.s.x[0].norm()), 0.0, 1e-4);
  EXPECT_NEAR(double(sc.s.bodies[0].x.y()), double(kT + kHalf), 1e-4);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
