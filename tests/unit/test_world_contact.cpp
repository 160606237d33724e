// A rigid body against the static world or another body
// (xpbd::BodyWorldContact, xpbd/src/rigid_solve.cpp), without Bullet: a
// box's four lower corners on a horizontal plane, a box on a box, and two
// bodies meeting, against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "xpbd/xpbd.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;

constexpr Real kG = Real(9.81);
const Vec3 kHalf(0.2, 0.1, 0.15);  // m, the box's half extents

// An empty model (the body only) and a 2 kg box of half extents kHalf with
// its centre at height y, its four lower corners as contacts with the plane
// y = 0 (static friction mu).
struct Box {
  xpbd::Model m = xpbd::compile(xpbd::SceneDesc{});
  xpbd::State s = xpbd::make_state(m);
};
Box box_on_plane(Real y, Real mu, const Vec3& v = Vec3::Zero()) {
  Box u;
  xpbd::RigidBody b;
  const Real mass = 2;
  b.x = Vec3(0, y, 0);
  b.v = v;
  b.inv_mass = 1 / mass;
  const Vec3 e = 2 * kHalf;  // edge lengths
  b.inv_inertia = Vec3(12 / (mass * (e.y() * e.y() + e.z() * e.z())),
                       12 / (mass * (e.x() * e.x() + e.z() * e.z())),
                       12 / (mass * (e.x() * e.x() + e.y() * e.y())));
  b.accel = Vec3(0, -kG, 0);
  u.s.bodies.push_back(b);
  for (Real sx : {-1, 1})
    for (Real sz : {-1, 1}) {
      xpbd::BodyWorldContact c;
      c.body = 0;
      c.r = Vec3(sx * kHalf.x(), -kHalf.y(), sz * kHalf.z());
      c.p = Vec3(sx * kHalf.x(), 0, sz * kHalf.z());
      c.n = Vec3::UnitY();
      c.friction = mu;
      u.s.world_contacts.push_back(c);
    }
  return u;
}

xpbd::StepConfig config() {
  xpbd::StepConfig cfg;
  cfg.gravity.setZero();  // the body's own accel carries gravity
  return cfg;
}

TEST(WorldContact, BoxRestsOnThePlaneAtItsHalfHeight) {
  // Dropped flat from 5 cm (1 m/s at impact): after 2 s it rests with its
  // centre at the half height (within what gravity adds in one substep,
  // g h^2), and no corner moves faster than 1 mm/s: it neither bounces nor
  // walks. (One sequential pass over the four corners per sweep left it
  // walking at 1.7 mm/s, rotated by 0.07 rad after 20 s.)
  Box u = box_on_plane(kHalf.y() + Real(0.05), 0.5);
  const xpbd::StepConfig cfg = config();
  for (int k = 0; k < 120; ++k) xpbd::step(u.m, u.s, cfg);
  const xpbd::RigidBody& b = u.s.bodies[0];
  const Real h = cfg.dt / Real(cfg.substeps);
  EXPECT_NEAR(b.x.y(), kHalf.y(), kG * h * h);
  EXPECT_LT(b.v.norm() + b.w.norm() * kHalf.norm(), Real(1e-3));
  EXPECT_LT(b.q.angularDistance(xpbd::Quat::Identity()), Real(0.01));
}

TEST(WorldContact, StartingOverlapIsNeitherDeepenedNorTurnedIntoVelocity) {
  // The box starts 1 cm into the plane. Projected out inside a substep, the
  // overlap would leave it at 0.01 / h = 6 m/s upwards; the host (Bullet)
  // removes it with its own position correction. XPBD keeps the box from
  // going deeper: after a step it is where it started (within g h^2) and
  // at rest.
  Box u = box_on_plane(kHalf.y() - Real(0.01), 0.5);
  const xpbd::StepConfig cfg = config();
  xpbd::step(u.m, u.s, cfg);
  const xpbd::RigidBody& b = u.s.bodies[0];
  const Real h = cfg.dt / Real(cfg.substeps);
  EXPECT_NEAR(b.x.y(), kHalf.y() - Real(0.01), kG * h * h);
  EXPECT_LT(std::abs(b.v.y()), kG * h);
  ASSERT_EQ(u.s.world_contact_slack.size(), 4u);
  for (Real slack : u.s.world_contact_slack) EXPECT_NEAR(slack, Real(-0.01), Real(1e-6));
}

TEST(WorldContact, FrictionStopsASlidingBoxAndNoFrictionDoesNot) {
  // Pushed sideways at 0.01 m/s on the plane with mu = 0.5: Coulomb
  // friction stops it within v / (mu g) = 2 ms; after 0.5 s less than 1% of
  // the push is left (what the sequential solve leaves: about 1e-5 m/s).
  // Without friction it keeps its velocity (no other force along x).
  Box held = box_on_plane(kHalf.y(), 0.5, Vec3(0.01, 0, 0));
  Box sliding = box_on_plane(kHalf.y(), 0, Vec3(0.01, 0, 0));
  const xpbd::StepConfig cfg = config();
  for (int k = 0; k < 30; ++k) {
    xpbd::step(held.m, held.s, cfg);
    xpbd::step(sliding.m, sliding.s, cfg);
  }
  EXPECT_LT(std::abs(held.s.bodies[0].v.x()), Real(1e-4));
  EXPECT_LT(std::abs(held.s.bodies[0].x.x()), Real(0.01) * Real(0.01) / (Real(0.5) * kG));
  EXPECT_NEAR(sliding.s.bodies[0].v.x(), Real(0.01), Real(1e-6));
  EXPECT_NEAR(sliding.s.bodies[0].x.x(), Real(0.01) * 30 * cfg.dt, Real(1e-6));
}

// Two bodies meet head on in zero gravity, touching at the start: A (1 kg)
// at 1 m/s, B (3 kg) at rest, one contact along the line of their centres
// (no torque), on B's surface (other = B). Without restitution they move
// on together at the common velocity m_a v_a / (m_a + m_b) = 0.25 m/s, and
// the contact is not violated.
TEST(WorldContact, TwoBodiesMeetAndMoveOnTogetherWithTheirMomentum) {
  xpbd::Model m = xpbd::compile(xpbd::SceneDesc{});
  xpbd::State s = xpbd::make_state(m);
  xpbd::RigidBody a, b;
  a.inv_mass = 1;
  a.inv_inertia = Vec3::Constant(10);
  a.v = Vec3(1, 0, 0);
  b.inv_mass = Real(1) / 3;
  b.inv_inertia = Vec3::Constant(Real(10) / 3);
  b.x = Vec3(1, 0, 0);
  s.bodies = {a, b};
  xpbd::BodyWorldContact c;
  c.body = 0;
  c.r = Vec3(0.5, 0, 0);
  c.other = 1;
  c.p = Vec3(-0.5, 0, 0);
  c.n = Vec3(-1, 0, 0);
  c.friction = Real(0.5);
  s.world_contacts.push_back(c);
  const xpbd::StepConfig cfg = config();
  for (int k = 0; k < 10; ++k) xpbd::step(m, s, cfg);
  const Real tol = Real(1000) * std::numeric_limits<Real>::epsilon();
  EXPECT_NEAR(s.bodies[0].v.x(), Real(0.25), tol);
  EXPECT_NEAR(s.bodies[1].v.x(), Real(0.25), tol);
  EXPECT_NEAR(s.bodies[0].v.x() / s.bodies[0].inv_mass + s.bodies[1].v.x() / s.bodies[1].inv_mass, Real(1), tol);
  EXPECT_GE(s.bodies[1].x.x() - s.bodies[0].x.x(), Real(1) - tol);
  EXPECT_LT(s.bodies[0].w.norm() + s.bodies[1].w.norm(), tol);
}

// A box dropped flat from 5 cm onto a box lying on the plane: the top
// box's four lower corners against the lower box's top face (other = 0).
// After 2 s both rest, the top one at three half heights and the lower one
// at one, neither moving faster than 1 mm/s. Within 0.5 mm (the stack
// bound of docs/bullet-bridge.md): the sequential solve leaves both 0.13 mm
// low (the ground contacts are solved before the top box's weight reaches
// them in each pass), where a box alone rests within g h^2.
TEST(WorldContact, BoxRestsOnABoxOnThePlane) {
  Box u = box_on_plane(kHalf.y(), 0.5);
  xpbd::RigidBody top = u.s.bodies[0];
  top.x = Vec3(0, 3 * kHalf.y() + Real(0.05), 0);
  u.s.bodies.push_back(top);
  for (Real sx : {-1, 1})
    for (Real sz : {-1, 1}) {
      xpbd::BodyWorldContact c;
      c.body = 1;
      c.r = Vec3(sx * kHalf.x(), -kHalf.y(), sz * kHalf.z());
      c.other = 0;
      c.p = Vec3(sx * kHalf.x(), kHalf.y(), sz * kHalf.z());
      c.n = Vec3::UnitY();
      c.friction = Real(0.5);
      u.s.world_contacts.push_back(c);
    }
  const xpbd::StepConfig cfg = config();
  for (int k = 0; k < 120; ++k) xpbd::step(u.m, u.s, cfg);
  for (int i : {0, 1}) {
    const xpbd::RigidBody& b = u.s.bodies[std::size_t(i)];
    EXPECT_NEAR(b.x.y(), Real(1 + 2 * i) * kHalf.y(), Real(5e-4)) << "box " << i;
    EXPECT_LT(b.v.norm() + b.w.norm() * kHalf.norm(), Real(1e-3)) << "box " << i;
  }
}

TEST(WorldContact, BadContactsAreRejectedByName) {
  Box u = box_on_plane(kHalf.y(), 0.5);
  u.s.world_contacts[2].body = 3;
  try {
    xpbd::step(u.m, u.s, config());
    FAIL() << "no error";
  } catch (const xpbd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("world_contacts[2].body"), std::string::npos) << e.what();
  }
  u.s.world_contacts[2].body = 0;
  u.s.world_contacts[1].n = Vec3(0, 2, 0);
  EXPECT_THROW(xpbd::step(u.m, u.s, config()), xpbd::ConfigError);
  u.s.world_contacts[1].n = Vec3::UnitY();
  u.s.world_contacts[0].friction = -1;
  EXPECT_THROW(xpbd::step(u.m, u.s, config()), xpbd::ConfigError);
  u.s.world_contacts[0].friction = 0;
  u.s.world_contacts[3].other = 0;  // the body itself
  try {
    xpbd::step(u.m, u.s, config());
    FAIL() << "no error";
  } catch (const xpbd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("world_contacts[3].other: index 0"), std::string::npos) << e.what();
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
