#pragma once
// The marker an XpbdWorld adds to its Bullet world, to learn whether the
// world still exists when the XpbdWorld is destroyed (world.hpp, the
// constructor's comment).
//
// btCollisionWorld's destructor destroys the broadphase proxy of every
// object still in the world and clears its handle, but leaves its index in
// the world's array; removeCollisionObject clears both. So a marker that
// has no handle but still an index was in a world that has been destroyed.
// The marker's shape is empty and its collision filter group and mask are
// 0, so that no broadphase pair, ray or contact test includes it.
#include <BulletCollision/CollisionShapes/btEmptyShape.h>
#include <btBulletDynamicsCommon.h>

namespace xpbd_bullet {

class XpbdWorld;

namespace detail {

class WorldMarker : public btCollisionObject {
 public:
  explicit WorldMarker(XpbdWorld* owner);
  // Deleted by the application (a cleanup loop over the world's objects):
  // tells the owner, which then no longer knows whether the world lives.
  ~WorldMarker() override;
  WorldMarker(const WorldMarker&) = delete;
  WorldMarker& operator=(const WorldMarker&) = delete;

  // In a world that has since been destroyed.
  bool world_destroyed() const { return getBroadphaseHandle() == nullptr && getWorldArrayIndex() >= 0; }
  // In a world now.
  bool in_world() const { return getBroadphaseHandle() != nullptr; }

  XpbdWorld* owner;  // null once the owner has let it go

 private:
  btEmptyShape shape_;
};

}  // namespace detail
}  // namespace xpbd_bullet
