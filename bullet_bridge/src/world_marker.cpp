// The XpbdWorld's marker in its Bullet world (world_marker.hpp).
#include "world_marker.hpp"

#include "xpbd_bullet/world.hpp"

namespace xpbd_bullet {

namespace detail {

WorldMarker::WorldMarker(XpbdWorld* o) : owner(o) { setCollisionShape(&shape_); }

WorldMarker::~WorldMarker() {
  if (owner != nullptr) owner->marker_ = nullptr;
}

}  // namespace detail

bool XpbdWorld::world_gone() const { return marker_ != nullptr && marker_->world_destroyed(); }

}  // namespace xpbd_bullet
