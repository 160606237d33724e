// Which of the Bullet world and the XpbdWorld is destroyed first (issue 14,
// checked steps): the XpbdWorld's marker in the world (world_marker.hpp)
// tells its destructor whether the world is still there. In the bridge
// label, so it also runs under AddressSanitizer: a destructor that touched
// the destroyed world (removeAction, the tick callback, the dispatcher) is
// a use after free there. Without the marker's verdict (checked by making
// world_gone() return false): DestroyingTheBulletWorldFirst is a heap use
// after free, and NewWorldAtTheDestroyedWorldsAddress throws "this Bullet
// world already has an XpbdWorld".
#include <gtest/gtest.h>

#include <memory>
#include <new>
#include <vector>

#include "../integration/support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::XpbdWorld;

// A Bullet world whose parts outlive it, so that the world alone can be
// destroyed, and rebuilt at the same address (placement new into storage
// kept here).
struct BareWorld {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  alignas(16) unsigned char storage[sizeof(btDiscreteDynamicsWorld)];
  btDiscreteDynamicsWorld* world = nullptr;

  void create() {
    world = new (storage) btDiscreteDynamicsWorld(&dispatcher, &broadphase, &solver, &config);
    world->setGravity(btVector3(0, btScalar(-kG), 0));
  }
  void destroy() {
    world->~btDiscreteDynamicsWorld();
    world = nullptr;
  }
  ~BareWorld() {
    if (world != nullptr) destroy();
  }
};

// A dynamic 1 kg box hanging from a pinned 4-particle rope by a two-way
// attachment, with the ground plane below.
struct Scene {
  btStaticPlaneShape plane{btVector3(0, 1, 0), 0};
  btBoxShape cube{btVector3(btScalar(0.05), btScalar(0.05), btScalar(0.05))};
  std::unique_ptr<btRigidBody> ground, box;

  void add_to(btDiscreteDynamicsWorld& w) {
    ground = std::make_unique<btRigidBody>(btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &plane));
    btVector3 inertia;
    cube.calculateLocalInertia(1, inertia);
    box = std::make_unique<btRigidBody>(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, &cube, inertia));
    box->setWorldTransform(BulletWorld::at(Vec3(Real(0.35), Real(1.95), 0)));
    box->setActivationState(DISABLE_DEACTIVATION);
    w.addRigidBody(ground.get());
    w.addRigidBody(box.get());
  }
};


void couple(XpbdWorld& xw, Scene& sc) {
  System s = hanging_rope();
  const auto id = xw.add_system(s.model, s.state);
  xw.attach(id, 3, sc.box.get(), btVector3(0, btScalar(0.05), 0));
}

// The world goes first (freed), its bodies later: the XpbdWorld's
// destructor leaves the freed world alone (without the marker it removed
// its action from it: a heap use after free under AddressSanitizer).
TEST(WorldLifetime, DestroyingTheBulletWorldFirst) {
  BareWorld parts;  // its own world stays unused: this one is on the heap
  auto world = std::make_unique<btDiscreteDynamicsWorld>(&parts.dispatcher, &parts.broadphase, &parts.solver,
                                                         &parts.config);
  world->setGravity(btVector3(0, btScalar(-kG), 0));
  Scene sc;
  sc.add_to(*world);
  auto xw = std::make_unique<XpbdWorld>(*world);
  couple(*xw, sc);
  for (int k = 0; k < 30; ++k) world->stepSimulation(kDt, 1, kDt);
  EXPECT_LT(sc.box->getWorldTransform().getOrigin().y(), btScalar(1.95));  // it stepped, coupled
  world.reset();
  xw.reset();
}

// The world goes first, its bodies later: the XpbdWorld's destructor
// leaves the world alone. A new world at the same address then gets its
// own XpbdWorld while the old one still exists (the old registration is
// stale, not "this world already has an XpbdWorld"), and steps.
TEST(WorldLifetime, NewWorldAtTheDestroyedWorldsAddress) {
  BareWorld bw;
  bw.create();
  Scene sc;
  sc.add_to(*bw.world);
  auto xw = std::make_unique<XpbdWorld>(*bw.world);
  couple(*xw, sc);
  for (int k = 0; k < 30; ++k) bw.world->stepSimulation(kDt, 1, kDt);
  const btScalar fallen = sc.box->getWorldTransform().getOrigin().y();
  EXPECT_LT(fallen, btScalar(1.95));  // it stepped, coupled
  bw.destroy();

  bw.create();
  ASSERT_EQ(static_cast<void*>(bw.world), static_cast<void*>(bw.storage));
  Scene sc2;
  sc2.add_to(*bw.world);
  std::unique_ptr<XpbdWorld> xw2;
  ASSERT_NO_THROW(xw2 = std::make_unique<XpbdWorld>(*bw.world));
  couple(*xw2, sc2);
  for (int k = 0; k < 30; ++k) bw.world->stepSimulation(kDt, 1, kDt);
  EXPECT_EQ(xw2->last_stats().coupled, 1);
  EXPECT_NEAR(sc2.box->getWorldTransform().getOrigin().y(), fallen, btScalar(1e-4));

  xw.reset();  // the first world's XpbdWorld, long after its world
  for (int k = 0; k < 5; ++k) bw.world->stepSimulation(kDt, 1, kDt);
  EXPECT_EQ(xw2->last_stats().coupled, 1);  // the new world's XpbdWorld is untouched
  xw2.reset();
  bw.world->removeRigidBody(sc2.box.get());
  bw.world->removeRigidBody(sc2.ground.get());
}

// The usual order, and Bullet's own cleanup loop before it: every object
// removed from the world (the marker with them), or removed and deleted.
// The XpbdWorld then leaves the world as it found it: no action, the tick
// callback back, so the world steps on without it.
TEST(WorldLifetime, CleanupLoopsBeforeTheXpbdWorld) {
  for (const bool delete_objects : {false, true}) {
    SCOPED_TRACE(delete_objects ? "removed and deleted" : "removed");
    BareWorld bw;
    bw.create();
    Scene sc;
    sc.add_to(*bw.world);
    auto xw = std::make_unique<XpbdWorld>(*bw.world);
    EXPECT_EQ(bw.world->getNumCollisionObjects(), 3);  // ground, box, marker
    couple(*xw, sc);
    for (int k = 0; k < 10; ++k) bw.world->stepSimulation(kDt, 1, kDt);
    std::vector<btCollisionObject*> others;
    for (int i = bw.world->getNumCollisionObjects() - 1; i >= 0; --i) {
      btCollisionObject* o = bw.world->getCollisionObjectArray()[i];
      btRigidBody* rb = btRigidBody::upcast(o);
      if (rb != nullptr)
        bw.world->removeRigidBody(rb);
      else
        bw.world->removeCollisionObject(o);
      if (rb == nullptr) others.push_back(o);
    }
    ASSERT_EQ(others.size(), 1u);  // the marker is the one object that is not a rigid body
    if (delete_objects) delete others[0];
    xw.reset();
    EXPECT_EQ(bw.world->getNumCollisionObjects(), 0);
    // A step calls every action left in the world: a dangling one would be
    // read after its free (AddressSanitizer).
    bw.world->addRigidBody(sc.box.get());
    EXPECT_NO_THROW(bw.world->stepSimulation(kDt, 1, kDt));
    bw.world->removeRigidBody(sc.box.get());
  }
}

// The broadphase pairs nothing with the marker (collision filter group and
// mask 0): a dynamic box around the origin, where the marker sits, has no
// overlapping pair. (Its shape is empty, so a pair would make no contact
// either, but each pair costs the dispatcher an algorithm every step.)
TEST(WorldLifetime, TheMarkerHasNoBroadphasePair) {
  BareWorld bw;
  bw.create();
  bw.world->setGravity(btVector3(0, 0, 0));
  XpbdWorld xw(*bw.world);
  btBoxShape cube(btVector3(1, 1, 1));
  btVector3 inertia;
  cube.calculateLocalInertia(1, inertia);
  btRigidBody box(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, &cube, inertia));
  bw.world->addRigidBody(&box);
  bw.world->stepSimulation(kDt, 1, kDt);
  EXPECT_EQ(bw.world->getBroadphase()->getOverlappingPairCache()->getNumOverlappingPairs(), 0);
  bw.world->removeRigidBody(&box);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
