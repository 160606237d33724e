// Smoke tests of the Bullet and FCL link, against closed-form answers. FCL
// is not a dependency of the bridge library (none of its code calls FCL);
// the tests that use it (this one, test_narrowphase_fcl) link it themselves
// (tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <fcl/narrowphase/distance.h>

#include <memory>

#include "xpbd_bullet/smoke.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

TEST(BridgeSmoke, BulletScalarMatchesXpbd) { EXPECT_TRUE(xpbd_bullet::bullet_scalar_matches()); }

TEST(BridgeSmoke, SphereComesToRestOnGroundAtItsRadius) {
  // A unit sphere dropped from 3 m rests with its centre 1 m above the plane
  // (Bullet's contact margin allows a few centimetres of slop).
  EXPECT_NEAR(xpbd_bullet::drop_sphere_on_ground(3.0, 3.0), 1.0, 0.05);
}

TEST(BridgeSmoke, FclSphereSphereDistanceIsCentreDistanceMinusRadii) {
  // Spheres of radius 0.5 and 0.25 m whose centres are 2 m apart.
  auto s1 = std::make_shared<fcl::Sphered>(0.5);
  auto s2 = std::make_shared<fcl::Sphered>(0.25);
  fcl::CollisionObjectd a(s1, fcl::Transform3d::Identity());
  fcl::Transform3d t = fcl::Transform3d::Identity();
  t.translation() = fcl::Vector3d(2.0, 0, 0);
  fcl::CollisionObjectd b(s2, t);
  fcl::DistanceRequestd req;
  fcl::DistanceResultd res;
  fcl::distance(&a, &b, req, res);
  EXPECT_NEAR(res.min_distance, 1.25, 1e-6);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
