// A 2 kg bar (1.2 x 0.06 x 0.06 m) dropped 1 m onto a 24 x 24 cloth of
// 0.4 kg lying on the ground, tilted 0.1 rad about z so that one end lands
// first, at the default settings and at fixed counts of 30 and 90 substeps.
//
// Closed form: every restitution is 0, so the landing takes energy out and
// puts none in. The bar's mechanical energy (kinetic, rotation included,
// plus potential) after the first touch never exceeds what it had before,
// and its centre of mass, which the end's impact only slows (a rod struck
// at its end keeps falling at about 3/4 of its speed), does not rise faster
// than a tenth of the landing speed (round-off and the cloth's give). The
// rise is asserted at the defaults; at the fixed counts, the energy.
//
// What it guards: the bar's straight motion over the step before the
// landing ended just short of the particles' centres (its acceleration,
// 2.7 mm over the step, was not in that motion, and a contact is needed
// within the thickness, not at the surface), so that step made no contact
// and carried the bar's end 7 mm into the cloth's band; the next step
// pushed it out within a substep, and the bar left at 4.2 m/s (6.3 m/s at
// 90 substeps, 21 m/s at 270; with the rotation, 28 J, 81 J and 487 J
// from 19.7 J). detail::particle_query now also takes the
// closest surface at the motion's end when the motion heads into it
// (bullet_bridge/src/world_impl.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

const Vec3 kHalf(0.6, 0.03, 0.03);  // m
constexpr Real kMass = 2;           // kg

Real energy(const btRigidBody& b) {
  const btVector3 w = b.getAngularVelocity();
  const btVector3 lw = b.getInvInertiaTensorWorld().inverse() * w;
  return Real(0.5) * kMass * Real(b.getLinearVelocity().length2()) + Real(0.5) * Real(w.dot(lw)) +
         kMass * kG * Real(b.getCenterOfMassPosition().y());
}

struct Landing {
  Real speed = 0;         // m/s, the bar's fall speed before the first touch
  Real rise = 0;          // m/s, the centre's largest upward speed after it
  Real e_before = 0;      // J, mechanical energy at the last frame before it
  Real e_after = 0;       // J, the largest after it
  int touch = -1;         // the frame of the first touch
  bool finite = true;
};

Landing drop(const SystemSettings& set) {
  BulletWorld bw;
  bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
  const Real t = xpbd_bullet::ContactSettings{}.thickness;
  btTransform pose = BulletWorld::at(Vec3(0, 2 * t + kHalf.y() + 1, 0));
  pose.setRotation(btQuaternion(btVector3(0, 0, 1), btScalar(0.1)));
  btRigidBody* bar = bw.add_body(new btBoxShape(bt(kHalf)), kMass, pose);
  XpbdWorld xw(bw.world());
  System sys = lying_cloth(1, 1, t);
  const auto id = xw.add_system(sys.model, sys.state, set);
  Landing r;
  for (int f = 0; f < 60; ++f) {
    const Real e = energy(*bar);
    const Real vy_before = Real(bar->getLinearVelocity().y());
    bw.step();
    if (!xw.error(id).empty() || !std::isfinite(energy(*bar))) {
      r.finite = false;
      return r;
    }
    const Real vy = Real(bar->getLinearVelocity().y());
    // The first touch: the step ends slower than free fall would leave it.
    if (r.touch < 0 && vy > vy_before - Real(0.5) * kG / 60) {
      r.touch = f;
      r.speed = -vy_before;
      r.e_before = e;
    }
    if (r.touch >= 0) {
      r.rise = std::max(r.rise, vy);
      r.e_after = std::max(r.e_after, energy(*bar));
    }
  }
  return r;
}

Landing run(const SystemSettings& set, const char* what) {
  const Landing r = drop(set);
  std::printf("bar landing on one end on a lying cloth, %s: touch at frame %d at %.3g m/s; largest rise after it "
              "%.3g m/s; energy %.4g J before, at most %.4g J after\n",
              what, r.touch, double(r.speed), double(r.rise), double(r.e_before), double(r.e_after));
  return r;
}

TEST(WorldBarLanding, OnOneEndGivesTheBarNoUpwardSpeedAtTheDefaults) {
  const Landing r = run(SystemSettings{}, "defaults");
  ASSERT_TRUE(r.finite);
  ASSERT_GE(r.touch, 0) << "the bar never touched the cloth";
  EXPECT_GT(r.speed, Real(3.5));  // the 1 m fall: sqrt(2 g h) = 4.4 m/s, less what the touching step cut
  EXPECT_LE(r.rise, Real(0.1) * r.speed);
  EXPECT_LE(r.e_after, r.e_before);
}

// At fixed counts the energy bound holds (without the change: 28.3 J at
// 30 substeps, 81.5 J at 90, from 19.7 J). The rise does not: at 30 and 40
// substeps the bar's centre still rises at 1.4-1.6 m/s after its far end
// lands (docs/squeeze-surface-edges.md, "A bar landing on one end"), so it
// is printed, not asserted, here.
TEST(WorldBarLanding, OnOneEndPutsNoEnergyIntoTheBarAtFixedCounts) {
  for (const int n : {30, 90}) {
    SystemSettings set;
    set.substeps = n;
    set.tolerance.penetration = 0;  // a fixed count
    const std::string what = std::to_string(n) + " substeps";
    const Landing r = run(set, what.c_str());
    ASSERT_TRUE(r.finite) << what;
    ASSERT_GE(r.touch, 0) << what;
    EXPECT_LE(r.e_after, r.e_before) << what;
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
