// Smoke tests of the Bullet and FCL link, against closed-form answers.
#include <gtest/gtest.h>

#include "xpbd_bullet/smoke.hpp"

TEST(BridgeSmoke, BulletScalarMatchesXpbd) { EXPECT_TRUE(xpbd_bullet::bullet_scalar_matches()); }

TEST(BridgeSmoke, SphereComesToRestOnGroundAtItsRadius) {
  // A unit sphere dropped from 3 m rests with its centre 1 m above the plane
  // (Bullet's contact margin allows a few centimetres of slop).
  EXPECT_NEAR(xpbd_bullet::drop_sphere_on_ground(3.0, 3.0), 1.0, 0.05);
}

TEST(BridgeSmoke, FclSphereSphereDistanceIsCentreDistanceMinusRadii) {
  EXPECT_NEAR(xpbd_bullet::fcl_sphere_distance(0.5, 0.25, 2.0), 1.25, 1e-6);
}
