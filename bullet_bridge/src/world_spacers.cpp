// Spacers: the cloth between two bodies, made visible to Bullet's solver
// (ContactSettings::spacers).
//
// XPBD solves a particle between two bodies as a rigid spacer (its contacts
// with both are solved jointly), but it runs before Bullet's solver, and
// Bullet's own contacts (a third body striking one of the two, a pile
// settling) then push the bodies together as if the cloth were not there.
// The settle pass (world_settle.cpp) can only put the particle inside one
// of them. So, for every particle that has contacts with two bodies on
// opposite sides of it in this step (at least one of them dynamic), the
// bridge adds a contact point between the two bodies to Bullet for this
// step only: at the two contact points on their surfaces, along the
// direction between the surfaces' normals, at a distance of the gap minus
// the two contact thicknesses. Bullet's solver then keeps the bodies that
// far apart there, jointly with all their other contacts and joints, and
// lets them close a larger gap only that far within the step (a
// speculative contact). The points live in manifolds of their own (one per
// pair of bodies, from the world's dispatcher; Bullet keeps four points
// per manifold), created after XPBD's step in the pre-tick hook and
// released in updateAction after Bullet's solve.
#include <algorithm>
#include <cstddef>
#include <utility>

#include "world_impl.hpp"

namespace xpbd_bullet {

namespace {
// Normals at least this far from parallel (n_a . n_b <= -kOpposite): the
// particle is between the two surfaces, not in a corner of one body against
// the side of another.
constexpr Real kOpposite = Real(0.5);
}  // namespace

void XpbdWorld::add_spacer(const btCollisionObject* a, const btCollisionObject* b, const btVector3& pa,
                           const btVector3& pb, const btVector3& n, btScalar distance, btScalar friction) {
  // One manifold per pair: Bullet keeps at most four points in it, the
  // deepest and the three that span the largest area with it, as for its
  // own contacts.
  btPersistentManifold* pm = nullptr;
  for (btPersistentManifold* m : spacers_)
    if ((m->getBody0() == a && m->getBody1() == b) || (m->getBody0() == b && m->getBody1() == a)) {
      pm = m;
      break;
    }
  if (pm && pm->getBody0() == b) {  // the pair's manifold is (b, a): the point seen from b
    add_spacer(b, a, pb, pa, -n, distance, friction);
    return;
  }
  if (!pm) {
    pm = world_.getDispatcher()->getNewManifold(a, b);
    spacers_.push_back(pm);
  }
  btManifoldPoint pt(a->getWorldTransform().invXform(pa), b->getWorldTransform().invXform(pb), n, distance);
  pt.m_positionWorldOnA = pa;
  pt.m_positionWorldOnB = pb;
  pt.m_combinedFriction = friction;
  pt.m_combinedRestitution = 0;
  pm->addManifoldPoint(pt, true);
  ++stats_.spacers;
}

void XpbdWorld::add_spacers(System& s) {
  const xpbd::State& st = s.state;
  // The contacts grouped by particle (they are stored body by body).
  auto& order = spacer_order_;
  order.clear();
  for (std::size_t k = 0; k < st.contacts.size(); ++k)
    if (st.contacts[k].body >= 0) order.emplace_back(st.contacts[k].particle, k);
  if (order.empty()) return;
  std::sort(order.begin(), order.end());
  auto shadow = [&](const xpbd::BodyContact& c) -> const Shadow& {
    return shadows_[std::size_t(s.shadow_of_body[std::size_t(c.body)])];
  };
  // Two contacts of one particle: the bodies' contact points and normals at
  // their poses now (where Bullet's collision detection and solver take
  // them).
  for (std::size_t g = 0; g < order.size();) {
    std::size_t e = g + 1;
    while (e < order.size() && order[e].first == order[g].first) ++e;
    for (std::size_t i = g; i < e; ++i)
      for (std::size_t j = i + 1; j < e; ++j) {
        const xpbd::BodyContact& ca = st.contacts[order[i].second];
        const xpbd::BodyContact& cb = st.contacts[order[j].second];
        const Shadow& sa = shadow(ca);
        const Shadow& sb = shadow(cb);
        if (sa.obj == sb.obj || (!sa.dynamic && !sb.dynamic)) continue;
        const btTransform& ta = sa.obj->getWorldTransform();
        const btTransform& tb = sb.obj->getWorldTransform();
        const btVector3 na = ta.getBasis() * to_bt(ca.n), nb = tb.getBasis() * to_bt(cb.n);
        if (na.dot(nb) > -kOpposite) continue;
        const btVector3 pa = ta * to_bt(ca.r), pb = tb * to_bt(cb.r);
        const btVector3 n = (nb - na).normalized();  // from b towards a, as Bullet's normalWorldOnB
        const btScalar gap = (pa - pb).dot(n);
        if (gap < 0) continue;  // the surfaces cross there: not a layer between them
        // The cloth slips on its more slippery side.
        add_spacer(sa.obj, sb.obj, pa, pb, n, gap - btScalar(ca.thickness + cb.thickness),
                   btScalar(std::min(ca.dynamic_friction, cb.dynamic_friction)));
      }
    g = e;
  }
  // A particle attached rigidly to a body, with a contact with another: it
  // sits at its attachment point, so the other body's contact thickness
  // from that point.
  for (const Attachment& at : attachments_) {
    if (at.system != s.id || at.compliance != 0 || !in_world(world_, at.body) || !finite_body(at.body)) continue;
    auto it = std::lower_bound(order.begin(), order.end(), std::pair<Index, std::size_t>(at.particle, 0));
    for (; it != order.end() && it->first == at.particle; ++it) {
      const xpbd::BodyContact& cb = st.contacts[it->second];
      const Shadow& sb = shadow(cb);
      if (sb.obj == at.body || (!sb.dynamic && at.body->isStaticOrKinematicObject())) continue;
      const btTransform& tb = sb.obj->getWorldTransform();
      const btVector3 n = tb.getBasis() * to_bt(cb.n);
      const btVector3 pa = at.body->getCenterOfMassTransform() * at.local, pb = tb * to_bt(cb.r);
      const btScalar gap = (pa - pb).dot(n);
      if (gap < 0) continue;  // the attachment point is behind the other body's surface
      add_spacer(at.body, sb.obj, pa, pb, n, gap - btScalar(cb.thickness), btScalar(cb.dynamic_friction));
    }
  }
}

void XpbdWorld::release_spacers() {
  btDispatcher* const d = world_.getDispatcher();
  for (btPersistentManifold* m : spacers_) d->releaseManifold(m);
  spacers_.clear();
}

}  // namespace xpbd_bullet
