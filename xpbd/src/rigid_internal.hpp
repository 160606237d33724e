#pragma once
// Helpers shared by the rigid-body stages (rigid_solve.cpp) and the joint
// contact solve (contact_block.cpp). Internal to xpbd.
#include "xpbd/rigid.hpp"
#include "xpbd/state.hpp"

namespace xpbd::rigid::detail {

// Moves body b by the positional impulse p (kg*m, world) applied at world
// lever arm rw: dx = p/m, dtheta = I^-1 (rw x p) (Mueller et al. 2020, eq. 7-9).
inline void apply_position_impulse(RigidBody& b, const Vec3& rw, const Vec3& p) {
  if (b.inv_mass == Real(0)) return;
  b.x += b.inv_mass * p;
  const Vec3 dth = apply_inv_inertia(b, rw.cross(p));
  const Quat dq(Real(0), dth.x(), dth.y(), dth.z());
  b.q.coeffs() += Real(0.5) * (dq * b.q).coeffs();
  b.q.normalize();
}

// The same for a velocity impulse j (N*s).
inline void apply_velocity_impulse(RigidBody& b, const Vec3& rw, const Vec3& j) {
  if (b.inv_mass == Real(0)) return;
  b.v += b.inv_mass * j;
  b.w += apply_inv_inertia(b, rw.cross(j));
}

// Records a particle contact's position impulse p (kg*m) or velocity
// impulse j (N*s) on body `body` for State::body_contact_impulse (nothing
// for the static world, body < 0).
inline void record_push(State& s, Index body, const Vec3& p) {
  if (body >= 0) s.body_contact_push[static_cast<std::size_t>(body)] += p;
}
inline void record_impulse(State& s, Index body, const Vec3& j) {
  if (body >= 0) s.body_contact_impulse[static_cast<std::size_t>(body)] += j;
}

// A body index < 0 stands for the static world: this body never moves.
inline RigidBody& body_or_world(State& s, Index b) {
  static thread_local RigidBody world;  // inv_mass 0, at the origin, at rest
  return b < 0 ? world : s.bodies[b];
}

// A world contact's surface point p and normal n now (world frame), and
// the other body's lever arm ro to p (zero for the static world).
struct WorldFrame {
  Vec3 p, n, ro;
};
inline WorldFrame world_frame(const State& s, const BodyWorldContact& c) {
  if (c.other < 0) return WorldFrame{c.p, c.n, Vec3::Zero()};
  const RigidBody& o = s.bodies[static_cast<std::size_t>(c.other)];
  const Vec3 ro = o.q * c.p;
  return WorldFrame{o.x + ro, o.q * c.n, ro};
}
inline const RigidBody& body_or_world(const State& s, Index b) {
  static const RigidBody world;
  return b < 0 ? world : s.bodies[b];
}

// A particle contact at the body's current pose, for the particle at x:
// the contact plane's normal n (world), and p, the point of the plane under
// the particle (x's projection onto it), with rw its lever arm from the
// body's centre of mass (zero for the static world).
//
// The lever arm is the point under the particle, not the point c.r the
// contact was found at: the particle moves along the plane during the step,
// and the constraint's gradient for the body's rotation, from
// C = n.(x - X - R r) with n = R n_b, is (x - X) x n = rw x n for this rw.
// With c.r instead, the solve misjudges how a turn of the body moves the
// plane under the particle: particles 20 cm along an edge contact's plane
// from the edge, held by the ground under them, turned a bar about its
// long axis by 0.25 rad in one sweep and threw it off the cloth at 143 m/s
// (the squeeze at 200 substeps; docs/squeeze.md).
// The pushes on the particle and on the body then also act along one line,
// so the solve conserves angular momentum.
struct Frame {
  Vec3 p, n, rw;
};
inline Frame contact_frame(const RigidBody& b, const BodyContact& c, bool world, const Vec3& x) {
  if (world) return {x - c.n.dot(x - c.r) * c.n, c.n, Vec3::Zero()};
  const Vec3 n = b.q * c.n;
  const Vec3 anchor = b.x + b.q * c.r;
  const Vec3 p = x - n.dot(x - anchor) * n;
  return {p, n, p - b.x};
}


}  // namespace xpbd::rigid::detail
