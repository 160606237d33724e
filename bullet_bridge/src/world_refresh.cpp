// Contacts that stay complete inside a step (ContactSettings::refresh,
// xpbd::StepConfig::refresh_contacts): XpbdWorld finds each particle's
// contacts once per Bullet step, along the straight path from where the
// particle starts; the particles the solve carries off that path are
// queried again here, at the start of the substep in which they leave it,
// for the rest of the step.
#include <algorithm>
#include <limits>

#include "world_impl.hpp"
#include "xpbd/rigid_solve.hpp"

namespace xpbd_bullet {

void XpbdWorld::refresh_contacts(System& s, btScalar dt, int sub, std::span<const Index> escaped) {
  const xpbd::Model& m = *s.model;
  xpbd::State& st = s.state;
  const ContactSettings& cs = s.settings.contacts;
  const int substeps = s.step_substeps;
  const Real h = dt / Real(substeps);
  const Real rest = dt - Real(sub) * h;  // s, what is left of the step
  stats_.refreshed += static_cast<int>(escaped.size());

  // Candidates: the bodies around the particles' paths over the rest of the step.
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::max()), hi = -lo;
  Real rmax = 0;
  for (Index i : escaped) {
    const Vec3 a = st.x_prev[i], b = a + rest * st.v[i];
    lo = lo.cwiseMin(a).cwiseMin(b);
    hi = hi.cwiseMax(a).cwiseMax(b);
    rmax = std::max(rmax, m.radius[i]);
  }
  const Real grow = cs.margin + cs.thickness + rmax;
  lo.array() -= grow;
  hi.array() += grow;
  refresh_candidates_.clear();
  candidates(world_, lo, hi, refresh_candidates_, cs.filter_group, cs.filter_mask);

  const std::size_t before = st.contacts.size();
  // The contacts the particles already have, by (particle, body): a
  // refreshed contact replaces the pair's contact from earlier in the step
  // (in its place in the solve order) rather than adding a second one,
  // which would be solved twice in every sweep.
  refresh_pairs_.clear();
  for (std::size_t k = 0; k < before; ++k)
    refresh_pairs_.emplace(pair_key(st.contacts[k].particle, st.contacts[k].body), k);
  for (const btCollisionObject* obj : refresh_candidates_) {
    if (!finite_body(obj)) continue;
    // The body as XPBD has it at the start of this substep: its entry in
    // State::bodies, or (not yet in the step) its shadow moved freely.
    const int shi = shadow_for(obj, dt);
    Index body = -1;
    for (std::size_t k = 0; k < s.shadow_of_body.size(); ++k)
      if (s.shadow_of_body[k] == shi) body = static_cast<Index>(k);
    xpbd::RigidBody now = body >= 0 ? st.bodies[std::size_t(body)] : shadows_[std::size_t(shi)].initial;
    if (body < 0) {
      std::vector<xpbd::RigidBody> one{now};
      for (int k = 0; k < sub; ++k) {
        xpbd::rigid::predict_bodies(one, h);
        xpbd::rigid::update_body_velocities(one, h);
      }
      now = one.front();
    }
    const Shadow& sh = shadows_[std::size_t(shi)];
    // World points at the body's current pose -> the same body points at
    // the pose Bullet's shape is at.
    const btTransform current(to_bt(now.q), to_bt(now.x));
    const btTransform to_pose = sh.pose * current.inverse();
    const btTransform pose_inv = sh.pose.inverse();
    btVector3 amin, amax;
    obj->getCollisionShape()->getAabb(sh.pose, amin, amax);
    const Real extent = (to_vec(amax) - to_vec(amin)).norm();
    const Real ab = rest * now.accel.norm() * (now.inv_mass > Real(0) ? Real(1) : Real(0));
    const Real wb = now.w.norm() + (now.inv_mass > Real(0) ? rest * now.ang_accel.norm() : Real(0));
    for (Index i : escaped) {
      if (attached(s, obj, i)) continue;
      ++stats_.queries;
      const Real thick = m.radius[i] + cs.thickness;
      const Vec3 x = to_vec(to_pose * to_bt(st.x_prev[i]));
      const Vec3 rel = st.v[i] - now.v;
      const Real travel = rest * (rel.norm() + ab + wb * extent);
      ParticleContact c;
      const Real ahead = thick + cs.margin + rest * ab;
      if (!detail::particle_query(*obj, x, rest * rel, travel, thick + cs.margin + travel, ahead, cs.margin, c)) continue;
      if (body < 0) {
        // New in this step: in State::bodies at its state now, and in the
        // contact-free reference over the whole step.
        body = body_index(s, obj, dt);
        xpbd::RigidBody free = st.bodies[std::size_t(body)];
        std::vector<xpbd::RigidBody> one{free};
        for (int k = 0; k < substeps; ++k) {
          xpbd::rigid::predict_bodies(one, h);
          xpbd::rigid::update_body_velocities(one, h);
        }
        s.free_bodies.push_back(one.front());
        st.bodies[std::size_t(body)] = now;
      }
      const xpbd::BodyContact bc = detail::body_contact(cs, *obj, i, body, thick, pose_inv, c);
      const auto [it, added] = refresh_pairs_.emplace(pair_key(i, body), st.contacts.size());
      if (added)
        st.contacts.push_back(bc);
      else
        st.contacts[it->second] = bc;
      ++stats_.refresh_contacts;
    }
  }
  stats_.contacts += static_cast<int>(st.contacts.size() - before);
}

}  // namespace xpbd_bullet
