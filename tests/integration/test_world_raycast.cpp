// XpbdWorld's ray queries over its systems (world.hpp), against closed
// forms and against Bullet's own rayTest on a box whose top face lies where
// a cloth lies: the same fraction, point and normal (Bullet's convention).
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "support.hpp"
#include "xpbd/error.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::XpbdWorld;

constexpr Real kTol = std::numeric_limits<Real>::epsilon() * 64;

// A 1 m square cloth lying in the plane y = h over x in [x0, x0 + 1], z in [0, 1].
System flat_cloth(Real x0, Real h) {
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc d;
  d.nx = d.ny = 5;
  d.origin = Vec3(x0, h, 0);
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  xpbd::add_cloth_grid(scene, d);
  return make_system(scene);
}

TEST(WorldRaycast, NearestSystemFirstAsBulletsRayTest) {
  BulletWorld bw(Vec3::Zero());
  // Bullet's box: top face at y = 0.5 over x in [2, 3], z in [0, 1].
  bw.add_static_box(Vec3(Real(0.5), Real(0.5), Real(0.5)), BulletWorld::at(Vec3(Real(2.5), 0, Real(0.5))));
  XpbdWorld xw(bw.world());
  const System lower = flat_cloth(0, 0), upper = flat_cloth(0, Real(0.5)), beside = flat_cloth(2, Real(0.5));
  const auto a = xw.add_system(lower.model, lower.state);
  const auto b = xw.add_system(upper.model, upper.state);
  const auto c = xw.add_system(beside.model, beside.state);

  // Down through both stacked cloths: the upper one at 1/4 of the way, then the lower at 1/2.
  const btVector3 from(Real(0.6), 1, Real(0.3)), to(Real(0.6), -1, Real(0.3));
  const auto closest = xw.ray_test_closest(from, to);
  ASSERT_TRUE(closest.has_value());
  EXPECT_EQ(closest->system, b);
  EXPECT_NEAR(closest->hit.fraction, 0.25, kTol);
  const auto all = xw.ray_test_all(from, to);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].system, b);
  EXPECT_EQ(all[1].system, a);
  EXPECT_NEAR(all[1].hit.fraction, 0.5, kTol);
  EXPECT_NEAR(all[1].hit.distance, 1.0, kTol);

  // Bullet's rayTest against the box's top, and ours against the cloth lying
  // on it, along the same slanted segment: the same hit.
  const btVector3 f2(Real(2.2), 2, Real(0.2)), t2(Real(2.8), -1, Real(0.9));
  btCollisionWorld::ClosestRayResultCallback ref(f2, t2);
  bw.world().rayTest(f2, t2, ref);
  ASSERT_TRUE(ref.hasHit());
  const auto ours = xw.ray_test_closest(f2, t2);
  ASSERT_TRUE(ours.has_value());
  EXPECT_EQ(ours->system, c);
  EXPECT_NEAR(ours->hit.fraction, Real(ref.m_closestHitFraction), 1e-5);
  EXPECT_NEAR((ours->hit.point - vec(ref.m_hitPointWorld)).norm(), 0, 1e-5);
  EXPECT_NEAR((ours->hit.normal - vec(ref.m_hitNormalWorld)).norm(), 0, 1e-5);
  EXPECT_NEAR(ours->hit.fraction, 0.5, kTol);  // (2 - 0.5) / (2 - (-1))

  // Nothing beside the cloths.
  EXPECT_FALSE(xw.ray_test_closest(btVector3(5, 1, 5), btVector3(5, -1, 5)).has_value());
}

TEST(WorldRaycast, FailedSystemIsNotTestedAndBadRaysAreNamed) {
  BulletWorld bw;
  XpbdWorld xw(bw.world());
  const System lower = flat_cloth(0, 0), upper = flat_cloth(0, Real(0.5));
  const auto a = xw.add_system(lower.model, lower.state);
  const auto b = xw.add_system(upper.model, upper.state);
  xw.state(b).x[7] = Vec3::Constant(std::numeric_limits<Real>::quiet_NaN());
  bw.step();
  ASSERT_FALSE(xw.error(b).empty());
  ASSERT_TRUE(xw.error(a).empty());
  const auto all = xw.ray_test_all(btVector3(Real(0.6), 1, Real(0.3)), btVector3(Real(0.6), -1, Real(0.3)));
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].system, a);
  const btScalar inf = std::numeric_limits<btScalar>::infinity();
  for (const bool bad_from : {true, false}) {
    try {
      xw.ray_test_all(bad_from ? btVector3(inf, 0, 0) : btVector3(0, 1, 0),
                      bad_from ? btVector3(0, -1, 0) : btVector3(0, inf, 0));
      FAIL() << "no exception";
    } catch (const xpbd::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(bad_from ? "from" : "to"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("inf"), std::string::npos) << e.what();
    }
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
