// Sleeping systems (SystemSettings::sleep_speed, world.hpp).
//
// A 16 x 16 cloth of 0.4 kg (1 m square) dropped 5 cm onto a static plane,
// sleep_speed 1 cm/s, sleep_time 0.5 s. Closed forms: it comes to rest
// lying flat at the contact thickness above the plane; asleep, its state
// does not change at all. A 2 kg box then falls onto the sleeping cloth
// from 0.2 m: the cloth must wake before the box reaches it, and the box ends
// resting on it with its bottom at twice the thickness (one particle
// between box and ground, as in test_world_cloth_under_box). Had the wake
// been missed, the box would fall through to the ground (bottom at 0).
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

const Real kT = xpbd_bullet::ContactSettings{}.thickness;

SystemSettings sleepy() {
  SystemSettings s;
  s.sleep_speed = Real(0.01);
  s.sleep_time = Real(0.5);
  return s;
}

System flat_cloth(Real y, xpbd::ClothPins pins = xpbd::ClothPins::none) {
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc c;
  c.nx = c.ny = 16;
  c.mass = Real(0.4);
  c.origin = Vec3(Real(-0.5), y, Real(-0.5));
  c.u = Vec3::UnitX();
  c.v = Vec3::UnitZ();
  c.pins = pins;
  xpbd::add_cloth_grid(scene, c);
  return make_system(scene);
}

// Steps until the system sleeps (at most `frames`); returns the frame, or -1.
int step_until_asleep(BulletWorld& bw, const XpbdWorld& xw, xpbd_bullet::SystemId id, int frames) {
  for (int f = 0; f < frames; ++f) {
    bw.step();
    if (xw.sleeping(id)) return f;
  }
  return -1;
}

TEST(WorldSleep, ClothAtRestFallsAsleepAndABoxFallingOntoItWakesIt) {
  BulletWorld bw;
  bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
  XpbdWorld xw(bw.world());
  const System cloth = flat_cloth(kT + Real(0.05));
  const auto id = xw.add_system(cloth.model, cloth.state, sleepy());
  const int slept = step_until_asleep(bw, xw, id, 300);
  std::printf("asleep after %d frames\n", slept + 1);
  ASSERT_GE(slept, 0) << "never fell asleep in 5 s";
  // At rest, flat at the thickness.
  for (const Vec3& x : xw.state(id).x) ASSERT_NEAR(x.y(), kT, 1e-4);
  for (const Vec3& v : xw.state(id).v) ASSERT_EQ(v, Vec3::Zero());
  // Asleep: not stepped, nothing changes, no contact search.
  const xpbd::State before = xw.state(id);
  for (int f = 0; f < 30; ++f) {
    bw.step();
    ASSERT_TRUE(xw.sleeping(id));
    EXPECT_EQ(xw.last_stats().sleeping, 1);
    EXPECT_EQ(xw.last_stats().candidates, 0);
  }
  EXPECT_EQ(xw.state(id).time, before.time);
  EXPECT_EQ(xw.state(id).x, before.x);

  // The box, dropped from 0.2 m above the cloth (from 1 m, at 4.4 m/s, it
  // passes through an awake cloth too: 7 cm per step against the 1 cm
  // contact margin): it stays asleep while the box is far.
  const Vec3 half(Real(0.15), Real(0.05), Real(0.15));
  btRigidBody* box = bw.add_body(new btBoxShape(bt(half)), 2, BulletWorld::at(Vec3(0, Real(0.2) + half.y(), 0)));
  bw.step();
  EXPECT_TRUE(xw.sleeping(id)) << "woken by a body 0.2 m away";
  Real lowest = 1;
  bool woke = false;
  for (int f = 0; f < 180; ++f) {
    bw.step();
    woke = woke || !xw.sleeping(id);
    lowest = std::min(lowest, Real(box->getCenterOfMassPosition().y()) - half.y());
  }
  const Real bottom = Real(box->getCenterOfMassPosition().y()) - half.y();
  std::printf("box bottom at %.5f m after 3 s, lowest %.5f m (2 x thickness = %.3f m)\n", double(bottom),
              double(lowest), double(2 * kT));
  EXPECT_TRUE(woke);
  EXPECT_FALSE(xw.sleeping(id));  // the box, awake in Bullet, rests on it
  EXPECT_NEAR(bottom, 2 * kT, 1e-3);
  EXPECT_GT(lowest, kT);  // never through the cloth
}

TEST(WorldSleep, MovingAPinWakesIt) {
  BulletWorld bw;
  XpbdWorld xw(bw.world());
  // Hanging from its two top corners, with drag so that it settles.
  System cloth = flat_cloth(1, xpbd::ClothPins::top_corners);
  SystemSettings set = sleepy();
  set.drag = 5;
  const auto id = xw.add_system(cloth.model, cloth.state, set);
  ASSERT_GE(step_until_asleep(bw, xw, id, 600), 0) << "never fell asleep in 10 s";
  bw.step();
  ASSERT_TRUE(xw.sleeping(id));
  // Move pin 0 by 10 cm: the next step wakes it, and the pinned particle follows.
  const Vec3 target = xw.state(id).pin_target[0] + Vec3(Real(0.1), 0, 0);
  xw.state(id).pin_target[0] = target;
  bw.step();
  EXPECT_FALSE(xw.sleeping(id));
  const xpbd::Pin& pin = xw.model(id).get<xpbd::Pin>()[0];
  EXPECT_NEAR((xw.state(id).x[pin.p[0]] - target).norm(), 0, 1e-6);
}

TEST(WorldSleep, WakeOnRequestOrNewSettingsAndBadSettingsAreNamed) {
  BulletWorld bw;
  bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
  XpbdWorld xw(bw.world());
  const System cloth = flat_cloth(kT);
  const auto id = xw.add_system(cloth.model, cloth.state, sleepy());
  ASSERT_GE(step_until_asleep(bw, xw, id, 120), 0);
  xw.wake(id);
  EXPECT_FALSE(xw.sleeping(id));
  const Real t0 = xw.state(id).time;
  bw.step();
  EXPECT_GT(xw.state(id).time, t0);  // stepped
  ASSERT_GE(step_until_asleep(bw, xw, id, 120), 0);
  xw.set_settings(id, xw.settings(id));
  EXPECT_FALSE(xw.sleeping(id));
  ASSERT_GE(step_until_asleep(bw, xw, id, 120), 0);
  xw.set_material<xpbd::Distance>(id, 0, 1, xpbd::Material{Real(1e-6), 0});
  EXPECT_FALSE(xw.sleeping(id));
  // Off by default: the same cloth without sleep_speed never sleeps.
  const auto awake = xw.add_system(cloth.model, cloth.state);
  for (int f = 0; f < 120; ++f) bw.step();
  EXPECT_FALSE(xw.sleeping(awake));
  for (const auto& [field, speed, time] : {std::tuple{"sleep_speed", Real(-1), Real(1)},
                                          std::tuple{"sleep_time", Real(0.01), Real(0)}}) {
    SystemSettings bad = sleepy();
    bad.sleep_speed = speed;
    bad.sleep_time = time;
    try {
      xw.set_settings(id, bad);
      FAIL() << "no exception for " << field;
    } catch (const xpbd::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
}

TEST(WorldSleep, ClothUnderABodyThatBulletKeepsAwakeStaysAwake) {
  // The box on it would lose its support: the cloth must not sleep.
  BulletWorld bw;
  bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
  const Vec3 half(Real(0.15), Real(0.05), Real(0.15));
  btRigidBody* box = bw.add_body(new btBoxShape(bt(half)), 2, BulletWorld::at(Vec3(0, 2 * kT + half.y(), 0)));
  XpbdWorld xw(bw.world());
  const System cloth = flat_cloth(kT);
  const auto id = xw.add_system(cloth.model, cloth.state, sleepy());
  EXPECT_LT(step_until_asleep(bw, xw, id, 180), 0);
  EXPECT_NEAR(Real(box->getCenterOfMassPosition().y()) - half.y(), 2 * kT, 1e-3);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
