#pragma once
// State: what a scene *does*. One per simulated instance; mutable.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "xpbd/aligned.hpp"
#include "xpbd/chains.hpp"
#include "xpbd/trees.hpp"
#include "xpbd/constraint_types.hpp"
#include "xpbd/rigid.hpp"
#include "xpbd/spatial_hash.hpp"
#include "xpbd/types.hpp"

namespace xpbd {

namespace detail {
struct Hierarchy;
}

struct Model;

struct State {
  std::vector<Vec3> x;       // m, positions
  std::vector<Vec3> x_prev;  // m, positions at the start of the last substep
  std::vector<Vec3> v;       // m/s, velocities

  // Optional external force per particle (N), constant over a step. Empty =
  // none (and no cost). If non-empty it must have one entry per particle.
  std::vector<Vec3> f_ext;

  // Pin targets (m), one per Pin element. Set pin_target to where the pin
  // must be at the end of the next step; step() moves the target linearly
  // from its previous value over the substeps.
  std::vector<Vec3> pin_target;
  std::vector<Vec3> pin_target_prev;  // value at the start of the step (internal)
  std::vector<Vec3> pin_target_now;   // value in the current substep (internal)

  // Lagrange multipliers of the last substep, one array per constraint type,
  // parallel to Model's constraint arrays. lambda is in J*s^2/[C] (kg*m for
  // length constraints); the generalized force lambda/h^2 is in J/[C] (N for
  // lengths, N*m/rad for angles, Pa for volumes).
  std::array<std::vector<Real>, kNumConstraintTypes> lambda;

  // Penetration: side (+1 or -1) of each element's point relative to its
  // triangle at the start of the current step (internal, written by step()).
  std::vector<Real> penetration_side;
  // GlobalVolume: gradient scratch (m^2), one entry per
  // Model::global_volume_verts (internal, so step() does not allocate).
  std::vector<Vec3> volume_grad;

  // Rigid bodies and what touches them (rigid.hpp). Filled by the host (the
  // Bullet bridge, or the user) before a step; empty = none and no cost.
  std::vector<RigidBody> bodies;            // shadow states, read back after the step
  std::vector<BodyContact> contacts;        // found once per step
  std::vector<ContactLambda> contact_lambda;  // parallel to contacts (sized by step())
  // Contacts of one particle, as a chain through `contacts` (sized by
  // step(), internal): contact_head[k] is the first contact of k's particle,
  // contact_next[k] the next one or -1. A particle with two or more contacts
  // has them solved jointly (rigid_solve.hpp).
  std::vector<Index> contact_head, contact_next;
  // The attachments of the same particle (internal, sized by step()):
  // contact_attachment[k] is the first attachment of k's particle or -1,
  // attachment_next[a] the next attachment of a's particle or -1. The joint
  // solve takes them with the contacts (contact_block.cpp).
  std::vector<Index> contact_attachment, attachment_next;
  std::vector<Index> contact_last;  // per particle, -1 between steps (scratch)
  std::vector<BodyTriangleContact> triangle_contacts;  // rigid features vs soft triangles
  std::vector<ContactLambda> triangle_contact_lambda;  // parallel (sized by step())
  std::vector<BodyEdgeContact> edge_contacts;          // rigid edges vs soft edges
  std::vector<ContactLambda> edge_contact_lambda;      // parallel (sized by step())
  // Per edge contact (internal, sized by step()): the first contact of each
  // of its two particles, or -1 (rigid_edges.cpp: their friction follows
  // the edge contact's push).
  std::vector<std::array<Index, 2>> edge_contact_head;
  std::vector<BodyAttachment> attachments;
  std::vector<Real> attachment_lambda;      // kg*m, parallel to attachments (sized by step())
  // kg*m, world, parallel to attachments (sized by step()): the position
  // impulse each attachment gave its particle over the current substep's
  // projections, sum of dlambda * n (the body got minus it). Divided by h^2
  // it is the force on the particle (forces.hpp); unlike lambda it keeps the
  // direction of every projection (n turns between them).
  std::vector<Vec3> attachment_impulse;
  std::vector<BodyWorldContact> world_contacts;  // bodies against the static world
  std::vector<ContactLambda> world_contact_lambda;  // parallel (sized by step())
  std::vector<Real> world_contact_slack;  // m, <= 0: the overlap each starts the step with (step())
  // Internal (built by step()): the indices of each body's world contacts
  // with the static world (other < 0), body b's in
  // world_contact_of[world_contact_begin[b] .. world_contact_begin[b + 1]).
  std::vector<Index> world_contact_begin, world_contact_of;
  // N*s, world, parallel to bodies: the impulse the particles' contacts
  // (contacts and triangle_contacts: normal, friction, restitution) gave
  // each body over the last step, static bodies included. Attachments and
  // world contacts are not counted. Written by step().
  std::vector<Vec3> body_contact_impulse;
  std::vector<Vec3> body_contact_push;  // kg*m, scratch: the current substep's position impulses
  // StepConfig::refresh_contacts (internal, sized by step() when on): each
  // particle's path that the contacts cover, x(t) = path_x + (t - path_t) *
  // path_v for t in the step, and the particles that left it in a substep.
  std::vector<Vec3> path_x, path_v;
  std::vector<Real> path_t;
  std::vector<Index> escaped;

  // The coloured XPBD Distance sweep's scratch (distance_stream.hpp,
  // internal, sized by step()): particle records (x, y, z, 1/m), of the
  // substep's start too when some element is damped, the multipliers in
  // stream order (copied to lambda at the end of every step), and per
  // element the factors that are constant over a step: compliance/h^2,
  // 1/denominator, compliance*damping/h.
  AlignedVector<Real> stream_x, stream_x_prev;
  std::vector<Real> stream_lambda;
  std::vector<Real> stream_at, stream_inv_den, stream_gamma;
  // What the factors above (and the Tether ones below) were computed for:
  // the stream's DistanceStream::serial, the substep and whether damped.
  // A step with the same ones keeps them (they are the same bits).
  struct StreamFactors {
    std::uint64_t serial = 0;
    Real h = 0;
    bool damped = false;
  };
  StreamFactors stream_factors, tether_factors;
  // The same for the coloured XPBD DihedralBending sweep
  // (dihedral_stream.hpp; it reads the records above): the multipliers in
  // stream order, compliance/h^2 and compliance*damping/h.
  std::vector<Real> dihedral_lambda, dihedral_at, dihedral_gamma;
  // The same for the coloured XPBD Tether sweep (Model::tether_stream; it
  // reads the records above): the multipliers in stream order and the
  // per-element factors constant over a step.
  std::vector<Real> tether_lambda, tether_at, tether_inv_den, tether_gamma;
  // The direct chain and tree solves' scratch (StepConfig::direct_chains,
  // chains.hpp, trees.hpp).
  ChainScratch chain;
  TreeScratch tree;
  // StepConfig::hierarchy: the coarse levels of the model's Distance graph
  // (internal; built by the first step that uses them, immutable, shared
  // by copies of the state; rebuilt when the model's particle or Distance
  // count differs, so a state put to another model of the same counts must
  // have it reset to nullptr) and the positions the pass starts from.
  std::shared_ptr<const detail::Hierarchy> hierarchy;
  std::vector<Vec3> hierarchy_x;

  // Particle-particle collision (spatial_hash.hpp): hash and the pairs found
  // at the start of the current step. Empty when the model has it off.
  SelfCollisionState self_collision;

  Real time = 0;          // s, simulated time
  Real last_substep = 0;  // s, h of the last substep (for force estimates)
  // s, the step length the velocity update measures a shorter step against
  // (step.cpp, update_velocities): the last step's dt, shortened as time
  // passes. 0 before the first step.
  Real velocity_step = 0;
  // Gauss-Seidel sweeps run so far (StepConfig::alternate_sweeps counts its
  // parity across step() calls, so that a host stepping one substep of one
  // iteration at a time still alternates).
  std::uint64_t sweeps = 0;

  template <class T>
  std::vector<Real>& lambdas() {
    return lambda[type_index_v<T>];
  }
  template <class T>
  const std::vector<Real>& lambdas() const {
    return lambda[type_index_v<T>];
  }
};

// Creates a state at the model's initial positions and velocities.
State make_state(const Model& model);

}  // namespace xpbd
