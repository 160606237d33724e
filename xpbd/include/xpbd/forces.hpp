#pragma once
// Forces read from the XPBD multipliers of the last substep: the reaction at
// each pin, the force of each particle-body attachment, and the largest
// constraint force of each constraint type.
//
// Units and sign. State::lambda is in J*s^2/[C] (kg*m for length
// constraints) and h = State::last_substep; lambda/h^2 is the generalized
// force in J/[C] (N for lengths). A projection moves particle i by
// w_i * dlambda * grad_i C (solve.hpp), i.e. by h^2 * F_i / m_i, so an
// element with multiplier lambda exerts on particle i the force
//
//   F_i = (lambda / h^2) * grad_i C        (N, world frame).
//
// A stretched Distance link has C > 0 and lambda < 0: it pulls its two
// particles together. Everything here is read from the state at the end of
// the last step (so from the last substep's multipliers, which Method::xpbd
// resets every substep). Meaningful for Method::xpbd only: PBD's multipliers
// are not forces. At a converged static equilibrium these are the exact
// forces of the discrete system (no deformation enters: they are the
// multipliers); the error is the solver's residual.
#include <string>
#include <vector>

#include "xpbd/model.hpp"
#include "xpbd/state.hpp"
#include "xpbd/types.hpp"

namespace xpbd {

// The support of one pinned particle: a particle with a Pin element, or one
// of inverse mass 0 (kinematic) without one.
struct PinReaction {
  Index particle = 0;
  Index pin = -1;  // Pin element index, or -1 (kinematic particle without a Pin)
  // N, world: the force the support exerts on the particle system through
  // this particle. A chain of n particles of mass m hanging from a pinned
  // kinematic particle: (n - 1) m |g| upward.
  //  - kinematic particle (inverse mass 0): minus the sum of the forces the
  //    elements touching it (all types but Pin and GlobalVolume, and its
  //    attachments; not contacts) exert on it: what it passes on to the rest;
  //  - Pin with compliance > 0 on a movable particle: the Pin's own force
  //    (lambda/h^2) grad C, grad C = (x - target)/|x - target|;
  //  - Pin with compliance 0 on a movable particle: the particle ends each
  //    substep on its target, where grad C is undefined, so the force comes
  //    from the particle's balance, assuming its velocity did not change over
  //    the last substep (at rest, or moving steadily with its target):
  //    F = -m g - f_ext - (forces of the other elements and attachments on
  //    it; GlobalVolume and body contacts are not counted).
  Vec3 force = Vec3::Zero();
  bool from_balance = false;  // the last case
};

// One particle-body attachment (State::attachments, BodyAttachment).
struct AttachmentForce {
  Index attachment = 0;  // index into State::attachments
  Index particle = 0;
  Index body = -1;       // index into State::bodies, -1 = a fixed world point
  // N, world: the force the attachment exerts on the body (at its point);
  // it exerts -on_body on the particle. From State::attachment_impulse, the
  // sum of the last substep's dlambda * n (n = (x_p - p_b)/|x_p - p_b| at
  // each projection): on the particle impulse/h^2, whose magnitude is
  // |lambda|/h^2 when n did not turn. Any compliance, movable or kinematic
  // particle.
  Vec3 on_body = Vec3::Zero();
};

// The largest multiplier of one constraint type, as a force.
struct MaxConstraintForce {
  std::string type;   // the type's snake_case name ("distance", "pin"; profile.hpp)
  std::string unit;   // of the force: "N", "N*m/rad", "J", "Pa"
  Index count = 0;    // elements of that type
  Index element = -1; // index of the largest (-1 when count = 0)
  Real force = 0;     // max |lambda|/h^2 over the elements, in `unit`
};

// Per pinned particle, in particle order. `gravity` (m/s^2) is the step's
// (StepConfig::gravity), used by the balance of stiff pins only.
// Throws ConfigError if the state has not been stepped (last_substep 0) or
// does not match the model.
std::vector<PinReaction> pin_reactions(const Model& model, const State& state, const Vec3& gravity);

// Per State::attachments entry, in order.
std::vector<AttachmentForce> attachment_forces(const Model& model, const State& state);

// One entry per constraint type, in ConstraintTypes order.
std::vector<MaxConstraintForce> max_constraint_forces(const Model& model, const State& state);

// N per particle, world: the sum of the forces the elements of every
// constraint type but Pin and GlobalVolume exert on each particle (not
// attachments or contacts). Elements whose gradient is undefined at the
// final state contribute nothing.
std::vector<Vec3> constraint_forces_on_particles(const Model& model, const State& state);

}  // namespace xpbd
