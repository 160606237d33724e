// Sleeping systems (SystemSettings::sleep_speed): when a system falls
// asleep and what wakes it.
#include <algorithm>
#include <cmath>
#include <limits>

#include "world_impl.hpp"

namespace xpbd_bullet {

bool XpbdWorld::sleeping(SystemId id) const { return system(id).asleep; }

void XpbdWorld::wake(SystemId id) {
  System& s = system(id);
  s.asleep = false;
  s.quiet = 0;
}

bool XpbdWorld::awake_body_near(const Vec3& lo, const Vec3& hi, btScalar dt) const {
  const btScalar g = world_.getGravity().length();
  const btCollisionObjectArray& objs = world_.getCollisionObjectArray();
  for (int i = 0; i < objs.size(); ++i) {
    const btCollisionObject* o = objs[i];
    if (o->isStaticObject() || !o->isActive() || !o->hasContactResponse()) continue;
    btVector3 a, b;
    o->getCollisionShape()->getAabb(o->getWorldTransform(), a, b);
    // What it can travel in one step: its speed, plus gravity's for a
    // dynamic body, plus the turn of its farthest point.
    const btRigidBody* rb = btRigidBody::upcast(o);
    btScalar reach = 0;
    if (rb) {
      reach = dt * rb->getLinearVelocity().length() + (o->isKinematicObject() ? 0 : g * dt * dt);
      reach += dt * rb->getAngularVelocity().length() * (b - a).length() * btScalar(0.5);
    } else {
      reach = dt * o->getInterpolationLinearVelocity().length();
    }
    if (!std::isfinite(double(reach))) return true;  // cannot tell: wake
    const Vec3 blo = to_vec(a).array() - reach, bhi = to_vec(b).array() + reach;
    if ((blo.array() <= hi.array()).all() && (bhi.array() >= lo.array()).all()) return true;
  }
  return false;
}

bool XpbdWorld::must_wake(const System& s, btScalar dt) const {
  const xpbd::State& st = s.state;
  if (st.pin_target.size() != s.pins_asleep.size()) return true;
  for (std::size_t k = 0; k < st.pin_target.size(); ++k)
    if (st.pin_target[k] != s.pins_asleep[k]) return true;
  return awake_body_near(s.box_lo, s.box_hi, dt);
}

void XpbdWorld::update_sleep(System& s, btScalar dt) {
  const SystemSettings& set = s.settings;
  if (!(set.sleep_speed > Real(0))) return;
  xpbd::State& st = s.state;
  const xpbd::Model& m = *s.model;
  Real vmax2 = 0;
  for (const Vec3& v : st.v) vmax2 = std::max(vmax2, v.squaredNorm());
  bool quiet = vmax2 < set.sleep_speed * set.sleep_speed;
  // A dynamic body it touches (contacts, attachments) that Bullet keeps
  // awake would lose its support: the system stays awake with it.
  for (std::size_t i = 0; quiet && i < st.bodies.size(); ++i) {
    const Shadow& sh = shadows_[static_cast<std::size_t>(s.shadow_of_body[i])];
    if (sh.dynamic && sh.dynamic->isActive()) quiet = false;
  }
  if (!quiet) {
    s.quiet = 0;
    return;
  }
  s.quiet += Real(dt);
  if (s.quiet < set.sleep_time) return;
  // The box that wakes it: its particles, grown by the contact reach.
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::max()), hi = -lo;
  Real rmax = 0;
  for (xpbd::Index i = 0; i < m.num_particles(); ++i) {
    lo = lo.cwiseMin(st.x[i]);
    hi = hi.cwiseMax(st.x[i]);
    rmax = std::max(rmax, m.radius[i]);
  }
  const Real grow = set.contacts.margin + set.contacts.thickness + rmax;
  lo.array() -= grow;
  hi.array() += grow;
  // An awake body already near it would wake it at once.
  if (m.num_particles() > 0 && awake_body_near(lo, hi, dt)) {
    s.quiet = 0;
    return;
  }
  s.asleep = true;
  s.box_lo = lo;
  s.box_hi = hi;
  s.pins_asleep = st.pin_target;
  std::fill(st.v.begin(), st.v.end(), Vec3::Zero());
  s.report.clear();
}

}  // namespace xpbd_bullet
