#pragma once
// XpbdWorld: runs xpbd particle systems inside a user's Bullet world.
//
// Hook: a btActionInterface (see docs/bullet-bridge.md). Bullet calls
// updateAction() once per internal step, after it has integrated the rigid
// bodies; XpbdWorld then runs `substeps` XPBD substeps of that internal step's
// dt for every system it holds. Works in any btDiscreteDynamicsWorld,
// including btSoftRigidDynamicsWorld, next to btSoftBody bodies.
//
// Per internal step:
//   1. gravity: read from the world (world->getGravity()) every step;
//   2. candidates: Bullet's broadphase, over each system's AABB swept over
//      the step and grown by the contact margin;
//   3. contacts: one query per (particle, candidate) against the body's pose
//      at the start of the step (narrowphase.hpp), plus a sweep for particles
//      that travel farther than the margin; stored in the body's frame and
//      re-projected every substep. Pairs whose boxes are apart (the
//      particle's reach against the body's AABB) are culled first, which
//      never drops a contact (ContactSettings::cull, world.cpp);
//   4. shadow bodies: each touched or attached rigid body starts at its pose
//      at the start of the step (end pose minus one step of its velocity:
//      Bullet's integrator is x1 = x0 + dt v1) and moves with its velocity
//      (which already holds gravity) plus the contact corrections;
//   5. xpbd::step() for each system;
//   6. coupling: every dynamic body receives the change of its shadow's
//      linear and angular velocity as applyCentralImpulse/applyTorqueImpulse,
//      its position correction, and is woken.
//
// Rigid bodies may be removed from the world between steps: contacts and
// shadow bodies are rebuilt every step, so nothing about a removed body is
// used again. Attachments hold the btRigidBody pointer: an attachment whose
// body has been removed from the world is inactive (checked every step
// against the world's object array), but the body must not be deleted while
// an attachment still names it (remove_attachment first).
#include <btBulletDynamicsCommon.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "xpbd/model.hpp"
#include "xpbd/profile.hpp"
#include "xpbd/state.hpp"
#include "xpbd/step.hpp"

namespace xpbd_bullet {

// Contact settings of one particle system.
struct ContactSettings {
  bool enabled = true;
  xpbd::Real margin = xpbd::Real(0.01);  // m, speculative contact margin (>= 0)
  // Thickness added to every particle's radius (m, >= 0): the distance kept
  // from rigid surfaces.
  xpbd::Real thickness = xpbd::Real(0.005);
  // Friction coefficients of the soft material; combined with the rigid
  // body's getFriction() by product, as Bullet combines two rigid bodies.
  xpbd::Real static_friction = xpbd::Real(0.5);
  xpbd::Real dynamic_friction = xpbd::Real(0.5);
  // Restitution of the soft material, combined with the body's by product.
  xpbd::Real restitution = 0;
  xpbd::Real compliance = 0;  // m/N
  // Rigid features against the model's collision_triangles: box corners and
  // points along box edges at most this far apart (m, > 0), hull vertices.
  // Choose it below the soft mesh's edge length.
  xpbd::Real feature_spacing = xpbd::Real(0.01);
  // Bullet collision filter of the particle system.
  int filter_group = btBroadphaseProxy::DefaultFilter;
  int filter_mask = btBroadphaseProxy::AllFilter;
  // Skip the narrowphase for (particle, body) pairs whose boxes are apart.
  // Conservative: the same contacts in the same order as false, which
  // queries every (particle, candidate) pair (the brute-force reference for
  // tests and benchmarks).
  bool cull = true;
};

// Opt-in wall-clock breakdown of one system's steps (SystemSettings::times,
// docs/stages.md): the stages inside xpbd::step() and the bridge's own, in
// ns (std::chrono::steady_clock) and runs, summed over internal steps. As in
// xpbd::StageTimes, a stage without work is neither timed nor counted.
struct SystemTimes {
  xpbd::StageTimes step;  // inside xpbd::step() (xpbd/profile.hpp)
  // The bridge's stages:
  //   contacts  broadphase, culling, narrowphase, triangle contacts, and the
  //             shadow bodies of the bodies touched (when contacts are enabled);
  //   shadows   the attachments' shadow bodies and the bodies' contact-free
  //             reference motion (when the system has bodies);
  //   coupling  shadow changes -> impulses and position corrections on the
  //             dynamic bodies (when there are bodies; the per-body impulse
  //             application is shared by all systems, and its time is added
  //             to every timed system with bodies).
  enum Stage : std::size_t { contacts, shadows, coupling, count };
  std::array<std::int64_t, count> ns{};     // ns
  std::array<std::int64_t, count> calls{};  // runs with work
  static const char* name(std::size_t k) {
    constexpr std::array<const char*, count> names = {"bridge_contacts", "bridge_shadows",
                                                      "bridge_coupling"};
    return k < count ? names[k] : "?";
  }
};

struct SystemSettings {
  int substeps = 10;    // XPBD substeps per Bullet internal step (>= 1)
  int iterations = 1;   // Gauss-Seidel sweeps per substep (>= 1)
  xpbd::Method method = xpbd::Method::xpbd;
  xpbd::Real drag = 0;  // 1/s
  bool alternate_sweeps = false;  // xpbd::StepConfig::alternate_sweeps
  bool coloured = false;          // xpbd::StepConfig::coloured
  ContactSettings contacts;
  // Opt-in timing: when set, every step of the system adds its stage times
  // to *times (which must outlive the system or be reset to nullptr).
  // nullptr = no timing.
  SystemTimes* times = nullptr;
};

// Statistics of the last internal step, for tests and benchmarks.
struct StepStats {
  int candidates = 0;  // rigid bodies returned by the broadphase, summed over systems
  int contacts = 0;    // particle-body contacts created
  int queries = 0;     // (particle, body) pairs sent to the narrowphase
  // s, wall clock (std::chrono::steady_clock) spent finding the contacts
  // (broadphase, culling, narrowphase, triangle contacts), summed over systems.
  double contact_seconds = 0;
  int triangle_contacts = 0;  // rigid feature - soft triangle contacts created
  int shadows = 0;     // shadow bodies
};

class XpbdWorld : public btActionInterface {
 public:
  // Adds itself to `world` as an action; removes itself in the destructor.
  // The world must outlive this object.
  explicit XpbdWorld(btDiscreteDynamicsWorld& world);
  ~XpbdWorld() override;
  XpbdWorld(const XpbdWorld&) = delete;
  XpbdWorld& operator=(const XpbdWorld&) = delete;

  // Adds a particle system; returns its id (stable until removed). The state
  // must come from xpbd::make_state(*model) (or be a copy of one).
  int add_system(std::shared_ptr<const xpbd::Model> model, xpbd::State state,
                 const SystemSettings& settings = {});
  // Removes a system between steps. Throws std::out_of_range for an unknown id.
  void remove_system(int id);
  bool has_system(int id) const;

  // Attaches particle `particle` of system `id` to the point `local` (m, in
  // the body's centre-of-mass frame) of `body`: two-way if the body is
  // dynamic, one-way if it is static or kinematic. Returns an attachment id.
  // The body must be in the world; remove the attachment before deleting it.
  int attach(int id, xpbd::Index particle, btRigidBody* body, const btVector3& local,
             xpbd::Real compliance = 0);
  void remove_attachment(int attachment_id);

  xpbd::State& state(int id);
  const xpbd::State& state(int id) const;
  const xpbd::Model& model(int id) const;
  SystemSettings& settings(int id);

  const StepStats& last_stats() const { return stats_; }

  // btActionInterface
  void updateAction(btCollisionWorld* world, btScalar dt) override;
  void debugDraw(btIDebugDraw*) override {}

 private:
  struct System;
  struct Attachment;
  struct Shadow;
  System& system(int id);
  const System& system(int id) const;
  void step_system(System& s, btScalar dt);
  // Index into shadows_ of obj's shadow, created on first use in a step.
  int shadow_for(const btCollisionObject* obj, btScalar dt);
  // Index into State::bodies of obj's shadow for system s (added on first use).
  xpbd::Index body_index(System& s, const btCollisionObject* obj, btScalar dt);
  // Rigid feature points of the candidates against s's collision triangles.
  void find_triangle_contacts(System& s, btScalar dt, const xpbd::Vec3& lo, const xpbd::Vec3& hi);

  btDiscreteDynamicsWorld& world_;
  std::vector<std::unique_ptr<System>> systems_;
  std::vector<Attachment> attachments_;
  int next_id_ = 0;
  int next_attachment_ = 0;
  StepStats stats_;
  // Scratch, reused across steps.
  std::vector<const btCollisionObject*> candidates_;
  std::vector<Shadow> shadows_;  // bodies touched in the current internal step
  std::vector<xpbd::Vec3> features_;  // scratch: feature points of one body (body frame)
  std::vector<xpbd::Vec3> tri_lo_, tri_hi_;  // scratch: swept triangle bounds
};

}  // namespace xpbd_bullet
