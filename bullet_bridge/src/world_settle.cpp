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
//      box into the ground goes back above the ground;
//   4. steps 2 and 3 again for the particles the last round moved, up to
//      kSettleRounds rounds (a particle in a wedge between two bodies);
//      then step 1 again: the attachment has the last word over the
//      contacts. A particle attached to a body and squeezed against it by
//      another body is pushed out of that one by step 2, and the nearest
//      way out can be into its own body, where nothing pushes it out again
//      (it has no contact with the body it is attached to; the squeeze
//      application's bar had one 8.9 mm inside, docs/squeeze-surface-edges.md). Put back
//      at its point, it is inside the other body, which step 5 moves out;
//   5. with ContactSettings::wedges, each dynamic body that a particle is
//      still inside is moved out of it (below). Step 1 is not made again
//      after it: a body that step 5 moves leaves its attached particles
//      where they were (up to kWedgeShift thicknesses behind). Putting
//      them on it then made the float squeeze application's bar spin up
//      to 27 m/s (one seed of 32).
// So a frame ends with every contact of the step satisfied (but where a
// rigid attachment holds its particle against one), as it did when
// XPBD ran after Bullet (the action hook), where the pre-solve coupling
// alone left the violation Bullet's own contacts made (measured, xpbd-demo
// at the defaults: bullet_softdemo_cloth 73 mm -> 1.3e-15 m,
// cloth_on_sphere 0.061 mm -> 6e-17 m).
// Velocities are not changed (the next step's contacts see the relative
// velocity), so momentum is unchanged. Without step 5 a particle squeezed
// between two bodies that Bullet's solver pushed together (it does not see
// the cloth between them) can stay inside one of them. A particle that had
// no contact with a body in the step is not looked at.
#include <algorithm>
#include <cstddef>

#include "world_impl.hpp"
#include "xpbd_bullet/narrowphase.hpp"

namespace xpbd_bullet {

namespace {
// Rounds of the projection at most. Measured on the 49-body squeeze
// application (8 seeds, double): frames with a particle deeper than the
// thickness 19 with one round, 13 with 4, 13 with 16.
constexpr int kSettleRounds = 4;
// The most a body is moved out of a wedge in one step, in contact
// thicknesses (step 5).
constexpr Real kWedgeShift = 2;
}  // namespace

void XpbdWorld::settle(System& s) {
  const xpbd::Model& m = *s.model;
  xpbd::State& st = s.state;
  // Step 1 (and the end of step 4): each rigidly attached particle at its
  // point.
  const auto hold_attached = [&](bool count) {
    for (const Attachment& a : attachments_) {
      if (a.system != s.id || a.compliance != 0 || a.body->isStaticOrKinematicObject() ||
          m.inv_mass[std::size_t(a.particle)] == 0 || !in_world(world_, a.body) || !finite_body(a.body))
        continue;
      st.x[std::size_t(a.particle)] = to_vec(a.body->getCenterOfMassTransform() * a.local);
      if (count) ++stats_.settled;
    }
  };
  hold_attached(true);
  // Rounds of projections (Gauss-Seidel over each particle's contacts): a
  // particle in the wedge between two bodies, pushed out of one into the
  // other, is looked at again in the next round, until no particle moves
  // or kSettleRounds have run. Each round ends with the static bodies.
  auto& moved = settle_moved_;
  auto& next = settle_next_;
  moved.assign(st.x.size(), 1);
  for (int round = 0; round < kSettleRounds; ++round) {
    next.assign(st.x.size(), 0);
    bool any = false;
    for (const bool dynamic : {true, false}) {
      for (const xpbd::BodyContact& c : st.contacts) {
        const std::size_t p = std::size_t(c.particle);
        if (c.body < 0 || !moved[p] || m.inv_mass[p] == 0) continue;
        const Shadow& sh = shadows_[std::size_t(s.shadow_of_body[std::size_t(c.body)])];
        if ((sh.dynamic != nullptr) != dynamic || !finite_body(sh.obj)) continue;
        Vec3& x = st.x[p];
        if (!x.allFinite()) continue;  // query_point refuses it; the next step names it
        ParticleContact pc;
        if (!query_point(*sh.obj, x, c.thickness, pc) || pc.distance >= c.thickness) continue;
        x += (c.thickness - pc.distance) * pc.normal;
        next[p] = 1;
        any = true;
        ++stats_.settled;
      }
    }
    if (!any) break;
    moved.swap(next);
  }
  hold_attached(false);  // the end of step 4: the attachments have the last word over the contacts
  // 5. A particle still inside a dynamic body after the rounds is in a
  //    wedge: two bodies that Bullet's solver pushed together over the
  //    cloth (the spacers met only as far as its iterations went), or a
  //    heavy body on a particle on the ground, which one sweep per substep
  //    did not hold (the mass ratio; docs/tolerance.md). The
  //    body is moved out instead, by translation, along the surface normal
  //    at the particle, at most kWedgeShift contact thicknesses per step:
  //    the cloth between them is the rigid spacer that XPBD solved it as.
  //    A position correction only, as Bullet's split impulse makes (the
  //    velocities are unchanged, and the next step's contacts see them).
  if (!s.settings.contacts.wedges) return;
  for (const xpbd::BodyContact& c : st.contacts) {
    const std::size_t p = std::size_t(c.particle);
    if (c.body < 0 || m.inv_mass[p] == 0) continue;
    const Shadow& sh = shadows_[std::size_t(s.shadow_of_body[std::size_t(c.body)])];
    if (!sh.dynamic || !finite_body(sh.obj)) continue;
    const Vec3& x = st.x[p];
    if (!x.allFinite()) continue;
    // A particle attached to the body is held on it, not squeezed by it.
    const bool attached = std::any_of(attachments_.begin(), attachments_.end(), [&](const Attachment& a) {
      return a.system == s.id && std::size_t(a.particle) == p && a.body == sh.obj;
    });
    if (attached) continue;
    ParticleContact pc;
    if (!query_point(*sh.obj, x, c.thickness, pc) || pc.distance >= c.thickness) continue;
    const Real shift = std::min(c.thickness - pc.distance, kWedgeShift * c.thickness);
    btTransform t = sh.dynamic->getCenterOfMassTransform();
    t.setOrigin(t.getOrigin() - to_bt(Vec3(shift * pc.normal)));
    sh.dynamic->setCenterOfMassTransform(t);
    ++stats_.wedges;
  }
}

}  // namespace xpbd_bullet
