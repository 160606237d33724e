// Checked steps: what XpbdWorld does with a step length it cannot use, and
// with an attachment whose body has left the world (removed, or removed and
// deleted, its address perhaps reused by a new body). In the bridge label,
// so it also runs under AddressSanitizer: the deleted body must never be
// read.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "../integration/support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::XpbdWorld;

// A step whose length is not finite and > 0 (stepSimulation(dt, 0) passes
// it to the internal step as it is) steps no system: the particles stay
// where they were, nothing is thrown, StepStats::bad_dt says so, and the
// next good step goes on as if it had not happened. Before, the step of
// every system failed ("StepConfig.dt: must be finite and > 0") and the
// systems stayed frozen for good.
TEST(WorldChecked, StepLengthNotFiniteAndPositiveStepsNothing) {
  BulletWorld bw;
  bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
  XpbdWorld xw(bw.world());
  System s = hanging_rope();  // with contacts on (a ground plane far below)
  const auto id = xw.add_system(s.model, s.state);
  bw.step();
  const std::vector<Vec3> before = xw.state(id).x;
  for (const btScalar dt : {-kDt, std::numeric_limits<btScalar>::quiet_NaN(),
                            std::numeric_limits<btScalar>::infinity()}) {
    EXPECT_NO_THROW(bw.world().stepSimulation(dt, 0));
    EXPECT_EQ(xw.last_stats().bad_dt, 1) << dt;
    EXPECT_EQ(xw.error(id), "") << dt;
    EXPECT_EQ(xw.state(id).x, before) << dt;
  }
  bw.step();
  EXPECT_EQ(xw.last_stats().bad_dt, 0);
  EXPECT_EQ(xw.error(id), "");
  EXPECT_LT(xw.state(id).x[3].y(), before[3].y());  // it fell
}

// A 1 kg box (half extent 5 cm) beside the end of hanging_rope().
btRigidBody* box_beside_rope_end(BulletWorld& bw) {
  return bw.add_body(new btBoxShape(btVector3(0.05f, 0.05f, 0.05f)), 1, BulletWorld::at(Vec3(Real(0.35), 2, 0)));
}

// attach() names a bad argument and adds nothing: a particle out of range,
// a compliance that is negative or not finite, a local point that is not
// finite (before, a local point was accepted as it came).
TEST(WorldChecked, AttachNamesItsBadArgument) {
  BulletWorld bw;
  XpbdWorld xw(bw.world());
  System s = hanging_rope();
  const auto id = xw.add_system(s.model, s.state);
  btRigidBody* box = box_beside_rope_end(bw);
  const btScalar nan = std::numeric_limits<btScalar>::quiet_NaN();
  const struct {
    Index particle;
    btVector3 local;
    Real compliance;
    const char* named;
  } bad[] = {{4, btVector3(0, 0, 0), 0, "particle index 4"},
             {3, btVector3(0, 0, 0), -1, "compliance"},
             {3, btVector3(0, 0, 0), std::numeric_limits<Real>::infinity(), "compliance"},
             {3, btVector3(0, nan, 0), 0, "local point (0, nan, 0)"}};
  for (const auto& b : bad) {
    try {
      xw.attach(id, b.particle, box, b.local, b.compliance);
      ADD_FAILURE() << b.named << " accepted";
    } catch (const xpbd::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(b.named), std::string::npos) << e.what();
    }
  }
  bw.step();
  EXPECT_TRUE(xw.state(id).attachments.empty());
  for (const Vec3& x : xw.state(id).x) EXPECT_TRUE(x.allFinite());
}

// A body removed from the world and deleted ends its attachments at the
// next step and is never read again (under AddressSanitizer a read is a
// use-after-free).
TEST(WorldChecked, AttachmentEndsWhenItsBodyIsDeleted) {
  BulletWorld bw;
  XpbdWorld xw(bw.world());
  System s = hanging_rope();
  const auto id = xw.add_system(s.model, s.state);
  btRigidBody* box = box_beside_rope_end(bw);
  const auto att = xw.attach(id, 3, box, btVector3(0, 0, 0));
  bw.step();
  ASSERT_TRUE(xw.has_attachment(att));
  bw.remove_and_delete(box);
  bw.step();
  EXPECT_FALSE(xw.has_attachment(att));
  EXPECT_EQ(xw.last_stats().dropped_attachments, 1);
  EXPECT_EQ(xw.error(id), "");
  EXPECT_THROW(xw.remove_attachment(att), std::out_of_range);
  bw.step();
  EXPECT_EQ(xw.last_stats().dropped_attachments, 0);
}

// A new body built at a deleted body's address (placement new into the same
// storage: what an allocator that reuses the block does) does not take the
// attachment over. With bodies known by address alone (the check switched
// off), the rope's end moved 11.7 m towards the new body in one step, and
// the new body 38 m towards the rope.
TEST(WorldChecked, NewBodyAtADeletedBodysAddressDoesNotTakeItsAttachment) {
  BulletWorld bw;
  XpbdWorld xw(bw.world());
  System s = hanging_rope();
  const auto id = xw.add_system(s.model, s.state);
  btBoxShape shape(btVector3(0.05f, 0.05f, 0.05f));
  btVector3 inertia(0, 0, 0);
  shape.calculateLocalInertia(1, inertia);
  alignas(alignof(btRigidBody)) unsigned char storage[sizeof(btRigidBody)];
  auto make = [&](const Vec3& at) {
    btRigidBody::btRigidBodyConstructionInfo info(1, nullptr, &shape, inertia);
    info.m_startWorldTransform = BulletWorld::at(at);
    auto* b = new (storage) btRigidBody(info);
    b->setActivationState(DISABLE_DEACTIVATION);
    bw.world().addRigidBody(b);
    return b;
  };
  btRigidBody* box = make(Vec3(Real(0.35), 2, 0));
  const auto att = xw.attach(id, 3, box, btVector3(0, 0, 0));
  bw.step();
  bw.world().removeRigidBody(box);
  box->~btRigidBody();
  btRigidBody* other = make(Vec3(50, 2, 0));
  ASSERT_EQ(static_cast<void*>(other), static_cast<void*>(box));
  bw.step();
  EXPECT_FALSE(xw.has_attachment(att));
  EXPECT_EQ(xw.last_stats().dropped_attachments, 1);
  // The rope's end hangs where it was, one step of fall from the box's place.
  EXPECT_LT((xw.state(id).x[3] - Vec3(Real(0.3), 2, 0)).norm(), Real(0.1));
  EXPECT_LT(other->getCenterOfMassPosition().distance(btVector3(50, 2, 0)), btScalar(0.01));
  bw.world().removeRigidBody(other);
  other->~btRigidBody();
}

// Removed and added again (Bullet's way to change a body's filter): the
// attachment has ended all the same, and says so; attach again to keep it.
TEST(WorldChecked, BodyAddedAgainNeedsANewAttachment) {
  BulletWorld bw;
  XpbdWorld xw(bw.world());
  System s = hanging_rope();
  const auto id = xw.add_system(s.model, s.state);
  btRigidBody* box = box_beside_rope_end(bw);
  const auto att = xw.attach(id, 3, box, btVector3(0, 0, 0));
  bw.step();
  bw.world().removeRigidBody(box);
  bw.world().addRigidBody(box);
  bw.step();
  EXPECT_FALSE(xw.has_attachment(att));
  EXPECT_EQ(xw.last_stats().dropped_attachments, 1);
  const auto again = xw.attach(id, 3, box, btVector3(0, 0, 0));
  bw.step();
  EXPECT_TRUE(xw.has_attachment(again));
  EXPECT_EQ(xw.last_stats().dropped_attachments, 0);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
