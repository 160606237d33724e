// After Bullet's solve and integration (updateAction): particles that a
// dynamic body's final pose has closed over are put back outside it
// (ContactSettings::settle).
//
// XPBD runs before Bullet's solver, against each coupled body's predicted
// motion. Bullet's own contacts and joints then move the body further: a
// box struck by another box, a body pushed down by what lands on it. Those
// changes reach XPBD only in the next step, so at the end of this one a
// light cloth can be centimetres inside a body it was resting against
// (measured: the 49-body squeeze application, docs/bullet-bridge.md).
//
// The settle pass is a position projection of the particles alone, with
// the bodies taken as they are (infinitely heavy against the particles):
//   1. each particle attached rigidly (compliance 0) to a dynamic body is
//      put at its attachment point at the body's final pose;
//   2. each particle with a contact with a dynamic body in this step that
//      is closer to the body at its final pose than the contact's
//      thickness (particle radius plus ContactSettings::thickness) is moved
//      along the surface normal to that thickness;
//   3. then the same against the static and kinematic bodies it had a
//      contact with, which have the last word: a particle pushed out of a
//      box into the ground goes back above the ground.
// So a frame ends with every contact of the step satisfied, as it did when
// XPBD ran after Bullet (the action hook), where the pre-solve coupling
// alone left the violation Bullet's own contacts made (measured, xpbd-demo
// at the defaults: bullet_softdemo_cloth 73 mm -> 1.3e-15 m,
// cloth_on_sphere 0.061 mm -> 6e-17 m).
// Velocities are not changed (the next step's contacts see the relative
// velocity), and the bodies are not moved, so momentum is unchanged.
// A particle squeezed between two bodies that Bullet's solver pushed
// together (it does not see the cloth between them) can stay inside one of
// them: the pass does not separate the bodies. A particle that had no
// contact with a body in the step is not looked at.
#include <cstddef>

#include "world_impl.hpp"
#include "xpbd_bullet/narrowphase.hpp"

namespace xpbd_bullet {

void XpbdWorld::settle(System& s) {
  const xpbd::Model& m = *s.model;
  xpbd::State& st = s.state;
  for (const Attachment& a : attachments_) {
    if (a.system != s.id || a.compliance != 0 || a.body->isStaticOrKinematicObject() ||
        m.inv_mass[std::size_t(a.particle)] == 0 || !in_world(world_, a.body) || !finite_body(a.body))
      continue;
    st.x[std::size_t(a.particle)] = to_vec(a.body->getCenterOfMassTransform() * a.local);
    ++stats_.settled;
  }
  for (const bool dynamic : {true, false}) {
    for (const xpbd::BodyContact& c : st.contacts) {
      if (c.body < 0 || m.inv_mass[std::size_t(c.particle)] == 0) continue;
      const Shadow& sh = shadows_[std::size_t(s.shadow_of_body[std::size_t(c.body)])];
      if ((sh.dynamic != nullptr) != dynamic || !finite_body(sh.obj)) continue;
      Vec3& x = st.x[std::size_t(c.particle)];
      if (!x.allFinite()) continue;  // query_point refuses it; the next step names it
      ParticleContact pc;
      if (!query_point(*sh.obj, x, c.thickness, pc) || pc.distance >= c.thickness) continue;
      x += (c.thickness - pc.distance) * pc.normal;
      ++stats_.settled;
    }
  }
}

}  // namespace xpbd_bullet
