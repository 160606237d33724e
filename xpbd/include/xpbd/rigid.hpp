#pragma once
// Rigid bodies as seen by the particle solver: shadow states, particle-body
// contacts and particle-body attachments (Mueller et al. 2020, "Detailed rigid
// body simulation with extended position based dynamics").
//
// xpbd itself has no rigid-body dynamics of its own: a host (the Bullet
// bridge, or a user) fills State::bodies with each body's pose and velocity at
// the start of a step. During the substeps a body moves with that velocity
// (the host has already integrated gravity and its own forces into it) plus the
// corrections of the contacts and attachments that touch it, weighted by the
// generalized inverse mass 1/m + (r x n)^T I^-1 (r x n). After the step the
// host reads the body's velocity back and applies the change as an impulse.
// Bodies with inv_mass 0 are static or kinematic: they move with their
// velocity and are not pushed.
#include <Eigen/Geometry>
#include <array>
#include <limits>
#include <vector>

#include "xpbd/types.hpp"

namespace xpbd {

using Quat = Eigen::Quaternion<Real>;

struct RigidBody {
  Vec3 x = Vec3::Zero();           // m, centre of mass, world
  Quat q = Quat::Identity();       // orientation, body -> world
  Vec3 v = Vec3::Zero();           // m/s, linear velocity of the centre of mass
  Vec3 w = Vec3::Zero();           // rad/s, angular velocity, world frame
  Real inv_mass = 0;               // 1/kg; 0 = static or kinematic
  Vec3 inv_inertia = Vec3::Zero(); // 1/(kg m^2), principal axes of the body frame
  // Added to v and w at the start of every substep (symplectic Euler, as the
  // particles' gravity), for dynamic bodies only (inv_mass > 0): the host's
  // forces over the body's mass (gravity included), and its torques through
  // the world-frame inverse inertia. Zero: the host has already put them into
  // v and w (or there are none).
  Vec3 accel = Vec3::Zero();       // m/s^2, world
  Vec3 ang_accel = Vec3::Zero();   // rad/s^2, world
  // Pose at the start of the current substep (written by step()).
  Vec3 x_prev = Vec3::Zero();
  Quat q_prev = Quat::Identity();
};

// A particle touching the surface of a rigid body, found once per step by the
// host (speculatively, within a margin) and re-projected every substep:
//   C = n . (x_p - p_b) - thickness >= 0,  p_b = X + R r,  n = R n_body.
// The plane through p_b holds the particle; the body is pushed, and its
// friction taken, at its point of that plane under the particle (the
// particle moves along the plane during the step; rigid_internal.hpp).
// body < 0 means the static world: r and n are then world-frame values.
struct BodyContact {
  Index particle = 0;
  Index body = -1;                 // index into State::bodies, or -1
  Vec3 r = Vec3::Zero();           // m, contact point on the surface, body frame
  Vec3 n = Vec3::UnitY();          // unit surface normal (out of the body), body frame
  Real thickness = 0;              // m, particle radius plus surface thickness
  Real static_friction = 0;        // mu_s, dimensionless, combined from both materials (<= 0: none)
  Real dynamic_friction = 0;       // mu_d, dimensionless
  Real restitution = 0;            // e, normally in [0, 1] (<= 0: none)
  Real compliance = 0;             // m/N
};

// Pins a particle to a point of a rigid body (dynamic: two-way; kinematic or
// static: one-way): C = |x_p - p_b| = 0, p_b = X + R r.
struct BodyAttachment {
  Index particle = 0;
  Index body = -1;                 // index into State::bodies, or -1 for a fixed world point
  Vec3 r = Vec3::Zero();           // m, body frame (world if body < 0)
  Real compliance = 0;             // m/N
};

// The seed's penetration constraint with the point on a rigid body: a
// rigid feature point q = X + R r (a box corner, a point sampled along a box
// edge, a hull vertex) against a soft triangle (x1, x2, x3):
//   C = s (q - x1).n - thickness >= 0,  n = unit normal of the triangle,
// with the side s recorded when the contact is found (start of the step), so
// a corner that crossed the cloth during the step is pushed back. Gradients
// as Penetration::point_triangle (constraints_contact.hpp); the body takes
// its share through the generalized inverse mass along n. Coulomb friction
// between the feature point and the triangle's point under it (its
// barycentric weights w_i spread the triangle's share: inverse mass
// sum w_i^2 / m_i): at position level with the tangential multiplier
// clamped to static_friction lambda_n, then on the velocities with what is
// left of dynamic_friction lambda_n, over h (rigid_solve.cpp says why it is
// clamped, where a particle contact's is all-or-nothing).
//
// The plane stands for the triangle only near it. The contact acts while
// the feature lies at most reach + closing_speed h behind the plane (h: the
// substep), and is left alone deeper: there the triangle has turned away
// under the feature, or the feature has passed the triangle's edge, and
// pushing it back out of the plane moves the triangle's particles by that
// depth in one substep, as velocity. A frictionless cloth under a bar that
// lands and spins on it gained energy that way without bound
// (docs/feature-contacts.md, "Reach of a feature contact").
struct BodyTriangleContact {
  Index body = -1;                   // index into State::bodies (-1 = static world point)
  Vec3 r = Vec3::Zero();             // m, feature point, body frame (world if body < 0)
  std::array<Index, 3> tri{};        // particle indices of the soft triangle
  Real side = 1;                     // +1 or -1
  Real thickness = 0;                // m
  Real static_friction = 0;          // mu_s, >= 0
  Real dynamic_friction = 0;         // mu_d, >= 0
  // m, >= 0: how far behind the plane the contact acts (with closing_speed);
  // infinity = at any depth.
  Real reach = std::numeric_limits<Real>::infinity();
  // m/s, >= 0 and finite: how fast the feature and the triangle can close
  // in on each other; reach grows by closing_speed h in a substep of h.
  Real closing_speed = 0;
};

// A rigid body's edge (a box's: ends a, b in the body frame) against a
// soft edge (particles p[0], p[1]: an edge of the collision triangles),
// where a cloth folded tight over the body's edge has no face over the
// edge to meet. With e_r = b - a, e_s = x1 - x0 (world)
// and u, t the parameters of the two lines' closest points:
//   C = n.(x_s(t) - x_r(u)) - thickness >= 0,
//   n = +-e_r x e_s / |e_r x e_s|, the sign that leans towards `out`,
// out: the direction from the rigid edge the soft edge belongs on (the
// Bullet bridge takes the outward bisector of the box edge's two faces,
// docs/edge-contacts.md). The sign is taken again
// at every evaluation: e_r x e_s turns over as the two edges pass parallel
// (a soft edge lying across a spinning blade's edge does so every half
// turn), and a sign kept from the start of the step then pushed the soft
// edge into the body. While n leans less than kEdgeLean towards out (the
// soft edge points along out, and has no outside there) the contact does
// not act. The soft edge takes (1 - t) and t of the push; the body its
// share through its inverse mass along n at x_r(u). It acts while both
// closest points lie on their edges (u and t in [0, 1]; past an end the
// feature points and the particle contacts answer), the edges are more
// than about a degree from parallel, and within its reach (as
// BodyTriangleContact). Coulomb friction as BodyTriangleContact's: static
// at the position level after each push, between the soft edge's point
// x_s(t) and the body's point x_r(u); the rest of mu_d lambda_n on the
// new velocities (edge_contact_velocities).
inline constexpr Real kEdgeLean = Real(0.25);  // cosine
struct BodyEdgeContact {
  Index body = -1;                     // index into State::bodies (-1 = static world edge)
  Vec3 a = Vec3::Zero(), b = Vec3::Zero();  // m, the rigid edge's ends, body frame (world if body < 0)
  std::array<Index, 2> p{};            // the soft edge's particles
  Vec3 out = Vec3::UnitY();            // unit, body frame (world if body < 0)
  Real thickness = 0;                  // m
  Real reach = std::numeric_limits<Real>::infinity();  // m, >= 0 (BodyTriangleContact::reach)
  Real closing_speed = 0;              // m/s, >= 0 and finite
  Real static_friction = 0;            // mu_s, dimensionless (<= 0: none)
  Real dynamic_friction = 0;           // mu_d, dimensionless (<= 0: none)
};

// Whether triangle contact c, whose constraint is C (C >= 0 holds), is deep
// enough behind its plane to be left alone in a substep of h (its reach).
inline bool beyond_reach(const BodyTriangleContact& c, Real C, Real h) {
  return -(C + c.thickness) > c.reach + c.closing_speed * h;
}

// A rigid body resting on (or touching) the static world or another body:
// a point of the body against a half-space of the other's surface, found
// by the host (the Bullet bridge takes them from Bullet's contact
// manifolds):
//   C = n . (X + R r - p) >= 0,
// with n and p fixed in the world (other < 0), or fixed in body `other`
// (p = X_o + R_o p_o, n = R_o n_o: then `p` and `n` hold p_o and n_o).
// Solved in every sweep with position-level static friction, so that the
// body's support is there inside the substeps (a cloth landing on a box
// lying on the ground pushes it against the ground, not into it).
struct BodyWorldContact {
  Index body = 0;                  // index into State::bodies (a dynamic body)
  Vec3 r = Vec3::Zero();           // m, the body's contact point, body frame
  Vec3 p = Vec3::Zero();           // m, the surface point, world frame (other's frame if other >= 0)
  Vec3 n = Vec3::UnitY();          // unit normal of the surface, out of it, world frame (likewise)
  Real friction = 0;               // mu, static, dimensionless
  Index other = -1;                // index into State::bodies of the body whose surface it is, or -1
};

// Per-contact solver values of the current substep.
struct ContactLambda {
  Real normal = 0;   // kg*m, >= 0; force = normal / h^2
  Real tangent = 0;  // kg*m, static friction multiplier
  Real vn_start = 0; // m/s, relative normal velocity at the substep start (restitution)
  // Its friction was solved jointly with the particle's other contacts and
  // attachments, at the position level, dynamic part included (the velocity
  // pass leaves it).
  bool joint = false;
};

namespace rigid {

// World position of body point r (body frame) at the current pose.
inline Vec3 world_point(const RigidBody& b, const Vec3& r) { return b.x + b.q * r; }

// Generalized inverse mass of a body for a unit impulse along unit direction
// n applied at world lever arm rw (from the centre of mass).
inline Real inv_mass_along(const RigidBody& b, const Vec3& rw, const Vec3& n) {
  if (b.inv_mass == Real(0)) return Real(0);
  const Vec3 rn = b.q.conjugate() * rw.cross(n);
  return b.inv_mass + rn.dot(b.inv_inertia.cwiseProduct(rn));
}

// World-frame inverse inertia applied to a world vector.
inline Vec3 apply_inv_inertia(const RigidBody& b, const Vec3& a) {
  return b.q * b.inv_inertia.cwiseProduct(b.q.conjugate() * a);
}

// Velocity of the body's material point at world lever arm rw.
inline Vec3 point_velocity(const RigidBody& b, const Vec3& rw) { return b.v + b.w.cross(rw); }

}  // namespace rigid

}  // namespace xpbd
