#pragma once
// Substep stages for rigid bodies, body contacts and body attachments
// (see rigid.hpp). Called by step(); each costs nothing when its array is empty.
#include "xpbd/model.hpp"
#include "xpbd/rigid.hpp"
#include "xpbd/state.hpp"

namespace xpbd::rigid {

// Sizes the per-contact and per-attachment multiplier arrays to the host's
// lists (allocates only when a list outgrows its capacity) and checks every
// index; throws ConfigError naming the bad element.
void begin_step(const Model& m, State& s);

// After the host appended contacts (from index first_contact) and bodies
// (from first_body) inside a step (StepConfig::refresh_contacts): checks
// them as begin_step does and sizes the arrays parallel to them; what the
// existing ones hold is kept.
void contacts_added(const Model& m, State& s, std::size_t first_contact, std::size_t first_body);

// Records each contact's relative normal velocity (restitution) and zeroes the
// multipliers. Call before predict.
void begin_substep(const Model& m, State& s);

// x_prev = x, q_prev = q; for dynamic bodies v += h accel, w += h ang_accel,
// and w's torque-free change (the gyroscopic term, implicit; not for an
// isotropic body); then x += h v, q += h/2 [w, 0] q (normalized).
void predict_bodies(std::vector<RigidBody>& bodies, Real h);

// One Gauss-Seidel pass over body attachments, then body contacts (normal
// push with static Coulomb friction at position level).
void solve_attachments(const Model& m, State& s, Real h);
void solve_contacts(const Model& m, State& s, Real h);
// The friction of one particle's contacts, the chain from contact `head`
// (State::contact_head): jointly, or one by one where the joint solve does
// not apply (as solve_contacts does after their normal parts).
void solve_particle_friction(const Model& m, State& s, std::size_t head, Real inv_h2);
// Rigid features against soft triangles (BodyTriangleContact): normal push
// within each contact's reach, then static Coulomb friction at position
// level.
void solve_triangle_contacts(const Model& m, State& s, Real h);
// Rigid edges against soft edges (BodyEdgeContact; rigid_edges.cpp): normal
// push within each contact's reach, then static Coulomb friction at
// position level, then the friction of the two particles' own contacts.
void solve_edge_contacts(const Model& m, State& s, Real h);
// Dynamic Coulomb friction of the edge contacts on the new velocities.
void edge_contact_velocities(const Model& m, State& s, Real h);
// Contact k's constraint C at the current positions, its gradient's unit
// normal side n, the soft edge's parameter t and the body's lever arm rw;
// false where it does not act (closest points past an end, parallel edges,
// beyond its reach in a substep of h). u, if given: the rigid edge's
// parameter (its point a + u (b - a) in the body frame).
bool edge_contact_constraint(const State& s, std::size_t k, Real h, Real& C, Vec3& n, Real& t, Vec3& rw,
                             Real* u_out = nullptr);
// Dynamic Coulomb friction of the rigid-feature-vs-triangle contacts on
// the new velocities (after the particle and body velocity updates).
void triangle_contact_velocities(const Model& m, State& s, Real h);
// Bodies against the static world (BodyWorldContact): normal push, then
// static Coulomb friction at position level.
void solve_world_contacts(State& s);
// Dynamic Coulomb friction of the bodies' world contacts on the new body
// velocities (after update_body_velocities).
void world_contact_velocities(State& s, Real h);

// The largest contact violation relative to its thickness over body
// contacts and rigid-feature-vs-triangle contacts: max over contacts of
// -C / thickness, where C >= 0 is the contact constraint (0 when every
// contact holds, 1 when a particle centre is on the body's surface). A
// triangle contact beyond its reach in a substep of h is not counted: the
// solve leaves it alone.
Real worst_contact_violation(const Model& m, const State& s, Real h);
// The same contacts' deepest violation in metres: max over contacts of -C
// (how far a particle, or a rigid feature, is inside the contact band of
// its thickness; 0 when every contact holds). A contact is measured against
// its body's pose in the state, so after a step: at the step's end. Triangle
// contacts beyond their reach (substep h) are not counted, as above.
Real deepest_contact_violation(const State& s, Real h);

// Adds the substep's position impulses of the particle contacts over h to
// State::body_contact_impulse (after the solve, before the velocity stage).
void collect_contact_impulses(State& s, Real h);

// v = (x - x_prev)/h and w from the quaternion change dq = q q_prev^-1 as
// (2/h) vec(dq) / dq.w, the exact inverse of predict_bodies' rotation step
// (dq.w taken as at least 1/2). With blend < 1 (a
// time step that shrank, step.cpp), a dynamic body keeps its predicted
// velocity plus only `blend` of the change the solve made to it.
void update_body_velocities(std::vector<RigidBody>& bodies, Real h, Real blend = 1);

// Dynamic Coulomb friction and restitution on velocities (after the
// particle and body velocity updates).
void contact_velocities(const Model& m, State& s, Real h, Real gravity_norm);

}  // namespace xpbd::rigid
