#pragma once
// XpbdWorld: runs xpbd particle systems inside a user's Bullet world, coupled
// both ways with its rigid bodies (docs/bullet-bridge.md).
//
// Hook: pre-solve coupling. XpbdWorld installs Bullet's pre-tick callback
// (btDynamicsWorld::setInternalTickCallback(..., isPreTick = true)), chained:
// a pre-tick callback the application had installed still runs, first, and
// the world's user info is left as it was. So XPBD runs in every internal
// step *before* Bullet's collision detection, constraint solver and
// integration, which then see what XPBD did to the rigid bodies. XpbdWorld is
// also an action (btActionInterface), which Bullet runs after integration:
// there it applies the residual below. Works in any btDiscreteDynamicsWorld,
// including btSoftRigidDynamicsWorld next to btSoftBody bodies.
//
// Per internal step of dt (pre_solve):
//   1. gravity: read from the world (world->getGravity()) every step;
//   2. candidates: Bullet's broadphase (AABBs brought up to date first), over
//      each system's AABB swept over the step and grown by the contact margin;
//   3. contacts: one query per (particle, candidate) against the body where
//      its shape is (a dynamic body at its start pose), plus a sweep for
//      particles that travel farther than the margin; stored in the body's
//      frame and re-projected every substep. Pairs whose boxes are apart are
//      culled first, which never drops a contact (ContactSettings::cull);
//   4. shadow bodies: each touched or attached rigid body starts at its pose
//      at the start of the step with the velocity Bullet will damp it to,
//      gains its forces over its mass (gravity included: getTotalForce) in
//      every substep, and takes the contact and attachment corrections;
//   5. xpbd::step() for each system;
//   6. hand-over, for every dynamic body some system coupled: its velocity is
//      set so that, after Bullet's damping and forces, it equals the shadow's
//      end velocity (Bullet's contacts and joints then act on top of it); the
//      residual (the shadow's end pose minus the pose Bullet's integration
//      reaches from that velocity, translation and rotation, zero for a body
//      at rest) is applied after integration, in updateAction;
//   7. spacers: for the particles between two bodies, contact points
//      between those bodies for Bullet's solver in this step
//      (ContactSettings::spacers), released in updateAction;
//   8. settle, in updateAction after the residuals: particles put back
//      outside the bodies' final poses (ContactSettings::settle).
// A coupled body therefore moves as the same body solved by XPBD at the
// substep, plus the changes of Bullet's own contacts and joints.
//
// One XpbdWorld per Bullet world (a second one is refused). If the
// application installs its own pre-tick callback after the XpbdWorld, the
// next updateAction finds the hook gone: it chains the new callback, puts its
// own back, and runs that one step late (StepStats::late).
//
// Errors: nothing is thrown out of stepSimulation. Settings are checked where
// they are set (add_system, set_settings). A rigid body whose pose or
// velocity is not finite is left out of every system's step (no contacts,
// its attachments inactive; StepStats::skipped_bodies) rather than stopping
// them. A system whose step fails all the same (a state so far blown up
// that a query refuses it) is no longer stepped; error(id) says why, and the
// other systems go on.
//
// Rigid bodies may be removed from the world between steps: contacts and
// shadow bodies are rebuilt every step, so nothing about a removed body is
// used again. Attachments hold the btRigidBody pointer: an attachment whose
// body has been removed from the world is inactive (checked every step
// against the world's object array), but the body must not be deleted while
// an attachment still names it (remove_attachment first).
#include "xpbd_bullet/precision_check.hpp"  // first: the float/double guard

#include <btBulletDynamicsCommon.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <compare>
#include <functional>
#include <ostream>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "xpbd/health.hpp"
#include "xpbd/materials.hpp"
#include "xpbd/model.hpp"
#include "xpbd/profile.hpp"
#include "xpbd/raycast.hpp"
#include "xpbd/state.hpp"
#include "xpbd/step.hpp"
#include "xpbd/workers.hpp"
#include "xpbd_bullet/settings.hpp"

namespace xpbd_bullet {

namespace detail {
class WorldMarker;
}  // namespace detail

// Statistics of the last internal step, for tests and benchmarks.
struct StepStats {
  int candidates = 0;  // rigid bodies returned by the broadphase, summed over systems
  int contacts = 0;    // particle-body contacts created
  int queries = 0;     // (particle, body) pairs sent to the narrowphase
  // s, wall clock (std::chrono::steady_clock) spent finding the contacts
  // (broadphase, culling, narrowphase, triangle contacts), summed over systems.
  double contact_seconds = 0;
  int triangle_contacts = 0;  // rigid feature - soft triangle contacts created
  // Of those, the ones only the path of a fast feature found (continuous
  // collision: ContactSettings::sweep_features).
  int swept_triangle_contacts = 0;
  // Rigid edge - soft edge contacts created (ContactSettings::edge_contacts).
  int edge_contacts = 0;
  // Features that reached 16 feature-triangle contacts in the step, the
  // most one gets (the first found; the rest of its candidate triangles are
  // not tested). A feature rests on a few triangles; many more come from a
  // thickness or margin far beyond the size of the cloth's triangles.
  int capped_features = 0;
  int shadows = 0;     // shadow bodies
  int coupled = 0;     // dynamic bodies handed a change (velocity and residual)
  int late = 0;        // 1 if this step ran from updateAction because the pre-tick hook had been replaced
  int failed = 0;      // systems whose step failed in this step (error(id) says why)
  int skipped_bodies = 0;  // bodies left out because their pose or velocity is not finite, summed over systems
  int sleeping = 0;        // systems asleep in this step (not stepped)
  // Particles queried again inside the step (ContactSettings::refresh),
  // summed over substeps and systems, and the contacts that gave.
  int refreshed = 0;
  int refresh_contacts = 0;
  // Particles moved by the settle pass after Bullet's integration
  // (ContactSettings::settle), summed over systems.
  int settled = 0;
  // Bodies moved out of a particle in a wedge by the settle pass (step 5
  // of world_settle.cpp: Bullet's solver pushed two bodies together over
  // the cloth), summed over contacts and systems.
  int wedges = 0;
  // Contact points added to Bullet between two bodies with cloth between
  // them (ContactSettings::spacers), summed over systems.
  int spacers = 0;
  // 1 if the step's length was not finite and > 0 (stepSimulation(dt, 0)
  // passes any dt on): no system was stepped, nothing was thrown.
  int bad_dt = 0;
  // Attachments ended in this step because their body had left the world
  // (XpbdWorld::attach).
  int dropped_attachments = 0;
  // Systems whose health (XpbdWorld::health) after this step is
  // over_stretched, exploded or nonfinite (a system whose step failed on a
  // state that is not finite counts here too).
  int over_stretched = 0;
  int exploded = 0;
  int nonfinite = 0;
  // With a tolerance (SystemSettings::tolerance): steps solved again with
  // more substeps, and systems that ended the step above their tolerance at
  // the cap (max_substeps, or 3 times the last step's count).
  int resolved = 0;
  int tolerance_missed = 0;
};

// A system's health after its last step (XpbdWorld::health): the library's
// classifier (xpbd/health.hpp) with SystemSettings::health, applied to the
// state after every step:
//   nonfinite       a particle position or velocity is NaN or infinite;
//   exploded        the particles' kinetic energy now exceeds energy_factor
//                   times the energy budget: the kinetic energy when the
//                   system was added, plus the gravity potential energy it
//                   has released since (its lowest point so far), plus the
//                   energy from outside: the most a body or pin touching it
//                   has been able to give (2 M v^2, M its movable mass, v the
//                   fastest contact or attachment point of a non-static body
//                   or the fastest moving pin target in any one step), plus
//                   every energy increase the application made between steps
//                   (moving particles, setting velocities);
//   over_stretched  a Distance element's strain |len/rest - 1| now exceeds
//                   max_strain;
//   ok              none of these.
// Not sticky: a system whose kinetic energy falls back below the bound is ok
// again.
struct SystemHealth {
  xpbd::Health status = xpbd::Health::ok;
  double max_strain = 0;      // 1, largest Distance strain after the step
  double kinetic_energy = 0;  // J, the movable particles' after the step
  double energy_budget = 0;   // J, xpbd::energy_budget of the system so far
  // Substeps of the last step (SystemSettings::substeps, or what the
  // tolerance chose), and whether the step met the tolerance (true without
  // one).
  int substeps = 0;
  bool tolerance_met = true;
  // m, with Tolerance::penetration set: the deepest contact violation after
  // the step's solve (xpbd::rigid::deepest_contact_violation); 0 otherwise.
  double penetration = 0;
};

// Typed ids: a system's id and an attachment's id cannot be mixed up (nor
// taken for a particle index). Each is made only explicitly from an int;
// .value is the number (stable until removed, never reused by a world).
struct SystemId {
  int value = -1;
  constexpr SystemId() = default;
  constexpr explicit SystemId(int v) : value(v) {}
  friend constexpr auto operator<=>(SystemId, SystemId) = default;
};
struct AttachmentId {
  int value = -1;
  constexpr AttachmentId() = default;
  constexpr explicit AttachmentId(int v) : value(v) {}
  friend constexpr auto operator<=>(AttachmentId, AttachmentId) = default;
};
inline std::ostream& operator<<(std::ostream& o, SystemId id) { return o << "system " << id.value; }
inline std::ostream& operator<<(std::ostream& o, AttachmentId id) { return o << "attachment " << id.value; }

// One body that a system's particles touched in the last internal step
// (XpbdWorld::contact_report).
struct BodyContactReport {
  const btCollisionObject* body = nullptr;
  // N*s, world: the total impulse the particles' contacts (normal push,
  // friction, restitution) applied to the body over the step, on the body
  // (the particles got the opposite). Divide by the step for the mean force.
  // Attachments are not contacts and are not counted.
  btVector3 impulse{0, 0, 0};
};

class XpbdWorld : public btActionInterface {
 public:
  // Called after each internal step in which the system stepped (at the end
  // of Bullet's internal step, after the residuals: states and bodies agree),
  // with the system's id and the step (s). It may read the system, change
  // settings, pins and materials, or remove systems and attachments. An
  // exception from it stops that system (error(id) starts with "step
  // callback: ") and is not thrown out of stepSimulation.
  using StepCallback = std::function<void(SystemId id, btScalar dt)>;

  // Installs the pre-tick hook (chained) and adds itself to `world` as an
  // action; both are removed in the destructor. Throws xpbd::ConfigError if
  // `world` already has an XpbdWorld.
  //
  // It also adds a marker to the world: a btCollisionObject with an empty
  // shape and collision filter group and mask 0 (no pair, ray or contact
  // test ever sees it; it is counted by getNumCollisionObjects). Bullet's
  // world destructor clears the broadphase handle of every object still in
  // it, which tells this object that the world is gone: destroying the
  // Bullet world first is then safe, and this object's destructor touches
  // nothing of it (only the destructor may be called after that). A cleanup
  // loop that removes the marker from the world (or also deletes it, as
  // loops that delete every collision object do) leaves this object unable
  // to tell: after one, destroy this object before the world.
  explicit XpbdWorld(btDiscreteDynamicsWorld& world);
  ~XpbdWorld() override;
  XpbdWorld(const XpbdWorld&) = delete;
  XpbdWorld& operator=(const XpbdWorld&) = delete;

  // Adds a particle system; returns its id (stable until removed). The state
  // must come from xpbd::make_state(*model) (or be a copy of one).
  SystemId add_system(std::shared_ptr<const xpbd::Model> model, xpbd::State state,
                 const SystemSettings& settings = {});
  // Removes a system between steps. Throws std::out_of_range for an unknown id.
  void remove_system(SystemId id);
  bool has_system(SystemId id) const;

  // Attaches particle `particle` of system `id` to the point `local` (m, in
  // the body's centre-of-mass frame) of `body`: two-way if the body is
  // dynamic, one-way if it is static or kinematic. Returns an attachment id.
  // The body must be in the world. An attachment ends at the first step
  // after its body has left the world (removed; removed and deleted; also
  // removed and added again, as Bullet's way to change a body's filter:
  // attach again): StepStats::dropped_attachments counts it and
  // has_attachment says false. A deleted body is never read, and a new body
  // at its address does not take its attachments over: a body is known by
  // the broadphase proxy it got when added, not by its address alone
  // (docs/bullet-bridge.md).
  AttachmentId attach(SystemId id, xpbd::Index particle, btRigidBody* body, const btVector3& local,
             xpbd::Real compliance = 0);
  void remove_attachment(AttachmentId attachment_id);
  // Whether the attachment exists (not removed, not ended with its body).
  bool has_attachment(AttachmentId attachment_id) const;

  // Why system `id`'s step failed ("" while it has not): the system is then
  // frozen, and nothing was thrown out of stepSimulation. Throws
  // std::out_of_range for an unknown id.
  const std::string& error(SystemId id) const;
  // The system's health after its last step (SystemHealth; all zero and ok
  // before the first). Throws std::out_of_range for an unknown id.
  const SystemHealth& health(SystemId id) const;

  xpbd::State& state(SystemId id);
  const xpbd::State& state(SystemId id) const;
  const xpbd::Model& model(SystemId id) const;
  // The system's settings. To change them, pass new ones to set_settings,
  // which checks them first: a bad value throws xpbd::ConfigError naming the
  // field and value there, and the system keeps its old settings. They take
  // effect at the next step; the system keeps its id and attachments.
  const SystemSettings& settings(SystemId id) const;
  void set_settings(SystemId id, const SystemSettings& settings);

  // Changes the material (compliance, damping) of elements [first, first +
  // count) of constraint type T of system `id`, e.g.
  //   xw.set_material<xpbd::Distance>(id, 0, n, {1e-4, 0});
  // (xpbd/materials.hpp). Checked here (xpbd::ConfigError naming the type,
  // range and value; nothing changes), in effect from the next step; the
  // system keeps its id, state and attachments. On the first change the
  // system gets its own copy of the model, so other systems and the
  // application's model (add_system's argument) keep the old material.
  template <class T>
  void set_material(SystemId id, std::size_t first, std::size_t count, const xpbd::Material& mat) {
    xpbd::set_material<T>(own_model(id), first, count, mat);
  }

  const StepStats& last_stats() const { return stats_; }

  // The bodies system `id`'s particles touched in its last step, each with
  // the impulse they applied to it (BodyContactReport); empty before the
  // first step and after a failed one. Read it between steps or from the
  // step callback.
  const std::vector<BodyContactReport>& contact_report(SystemId id) const;
  // Sets (or, with an empty function, removes) system `id`'s step callback.
  void set_step_callback(SystemId id, StepCallback callback);

  // Sleeping (SystemSettings::sleep_speed): whether system `id` is asleep,
  // and a request to wake it (it then steps from the next internal step and
  // needs sleep_time of quiet again before it can sleep).
  bool sleeping(SystemId id) const;
  void wake(SystemId id);

  // Ray queries against the systems' visible surfaces (xpbd/raycast.hpp:
  // Model::surface_triangles, both sides), as Bullet's rayTest: the segment
  // from -> to, hits at a fraction of the way in [0, 1]. Systems whose step
  // failed are not tested. Bullet's bodies are not tested either: call the
  // world's rayTest and keep the nearer of the two fractions. Throws
  // xpbd::ConfigError if from or to is not finite.
  struct RayHit {
    SystemId system;  // the system's id
    xpbd::RayHit hit;  // triangle, particles, barycentric weights, fraction, distance, point, normal
  };
  // The nearest hit over every system (equal fractions: lower system id).
  std::optional<RayHit> ray_test_closest(const btVector3& from, const btVector3& to) const;
  // Every hit, nearest first.
  std::vector<RayHit> ray_test_all(const btVector3& from, const btVector3& to) const;

  // One internal step of XPBD before Bullet's solver: the systems' steps and
  // the hand-over of velocities (see the top of this file). The pre-tick hook
  // calls it; call it yourself only to drive the bridge without Bullet's
  // stepSimulation (benchmarks), followed by updateAction after moving the
  // bodies.
  void pre_solve(btScalar dt);

  // btActionInterface: after Bullet's integration, applies the residual poses.
  void updateAction(btCollisionWorld* world, btScalar dt) override;
  // btActionInterface, called by the world's debugDrawWorld() when its
  // drawer's mode has DBG_DrawWireframe or DBG_DrawContactPoints (Bullet
  // calls the actions only for a mode with DBG_DrawWireframe, DBG_DrawAabb
  // or DBG_DrawNormals; call it yourself for contacts alone):
  //  - DBG_DrawWireframe: one line per Distance element of each system, or,
  //    for a system without Distance elements, the edges of its collision
  //    triangles; in the drawer's m_activeObject colour, or
  //    m_disabledSimulationObject for a system whose step failed;
  //  - DBG_DrawContactPoints: each particle-body contact of the system's last
  //    step (drawContactPoint: the point on the body, its normal, the
  //    particle's distance along it), in m_contactPoint colour.
  void debugDraw(btIDebugDraw* drawer) override;

 private:
  friend class detail::WorldMarker;
  struct System;
  struct Attachment;
  struct Shadow;
  struct Residual;
  struct Predicted;
  static void pre_tick(btDynamicsWorld* world, btScalar dt);  // the hook
  bool hook_installed() const;
  void install_hook();
  void run_callbacks(btScalar dt);  // the systems' step callbacks (updateAction)
  // Sleeping (world_sleep.cpp): after a step, whether s falls asleep; before
  // one, whether an asleep s must wake.
  void update_sleep(System& s, btScalar dt);
  bool must_wake(const System& s, btScalar dt) const;
  // Whether an awake non-static body can reach the box [lo, hi] within dt.
  bool awake_body_near(const xpbd::Vec3& lo, const xpbd::Vec3& hi, btScalar dt) const;
  System& system(SystemId id);
  const System& system(SystemId id) const;
  // The system's model, copied on first use so that it is the system's own.
  xpbd::Model& own_model(SystemId id);
  // Steps every system that has not failed (shadows_ filled, stats_ reset).
  void run_systems(btScalar dt);
  void step_system(System& s, btScalar dt);
  // Hands the coupled bodies' changes to Bullet (velocities now, residual
  // poses into residuals_ for updateAction).
  void hand_over(btScalar dt, bool late);
  // Index into shadows_ of obj's shadow, created on first use in a step.
  int shadow_for(const btCollisionObject* obj, btScalar dt);
  // Index into State::bodies of obj's shadow for system s (added on first use).
  xpbd::Index body_index(System& s, const btCollisionObject* obj, btScalar dt);
  // s's dynamic bodies' contact points with the static bodies they have a
  // Bullet manifold with (its points, and the bodies' vertices near them),
  // into State::world_contacts.
  void add_world_contacts(System& s, btScalar dt);
  // The contact search per broadphase candidate (s.contact.candidates[k]),
  // run on the threads of s's pool (SystemSettings::workers) when it has
  // one: each call only reads the world and s, and writes its own `out`
  // (and the thread's scratch). The contacts have body -1 until step_system
  // joins them in candidate order.
  struct CandidateContacts;  // world_impl.hpp
  struct FeatureScratch;     // world_impl.hpp
  // s's particles against candidate k (world_contacts.cpp).
  void particle_contacts_of(const System& s, std::size_t k, btScalar dt, CandidateContacts& out) const;
  // Before triangle_contacts_of: every collision triangle's box over the
  // step, and the hierarchy refitted to them (world_triangle_contacts.cpp).
  void triangle_bounds(System& s, btScalar dt);
  // Candidate k's rigid feature points against s's collision triangles; lo,
  // hi: the system's box over the step (world_triangle_contacts.cpp).
  void triangle_contacts_of(const System& s, std::size_t k, btScalar dt, const xpbd::Vec3& lo,
                            const xpbd::Vec3& hi, FeatureScratch& scratch, CandidateContacts& out) const;
  // The candidate's box edges against the edges of s's collision triangles
  // near them; lo, hi as above (ContactSettings::edge_contacts;
  // world_edge_contacts.cpp).
  void edge_contacts_of(const System& s, std::size_t k, btScalar dt, const xpbd::Vec3& lo, const xpbd::Vec3& hi,
                        FeatureScratch& fs, CandidateContacts& out) const;
  // Inside the step, at the start of substep `sub`: contacts for the
  // particles that left the path their contacts cover (world_refresh.cpp).
  void refresh_contacts(System& s, btScalar dt, int sub, std::span<const xpbd::Index> escaped);
  // After Bullet's integration: s's particles put back outside the bodies'
  // final poses (ContactSettings::settle; world_settle.cpp).
  void settle(System& s);
  // After XPBD's step, before Bullet's: contact points between the bodies
  // s's particles are squeezed between (ContactSettings::spacers;
  // world_spacers.cpp), into spacers_; released after Bullet's solve.
  void add_spacers(System& s);
  // One spacer point between a and b: pa, pb on their surfaces, n from b
  // towards a (Bullet's normalWorldOnB), distance m (< 0: too close).
  void add_spacer(const btCollisionObject* a, const btCollisionObject* b, const btVector3& pa,
                  const btVector3& pb, const btVector3& n, btScalar distance, btScalar friction);
  void release_spacers();
  // Divergence checks (SystemSettings::check_health; world_health.cpp):
  // before the solve, the energy the step starts with and what the
  // application and the bodies and pins touching s can put in; after the
  // step, s's SystemHealth and the StepStats counts.
  void health_before_solve(System& s, btScalar dt);
  void health_after_step(System& s);
  // Whether particle i of s is attached to obj.
  bool attached(const System& s, const btCollisionObject* obj, xpbd::Index i) const;

  // True once the Bullet world has been destroyed (world_marker.cpp).
  bool world_gone() const;
  btDiscreteDynamicsWorld& world_;
  // The marker in the world (the constructor's comment); null once the
  // application has deleted it.
  detail::WorldMarker* marker_ = nullptr;
  std::vector<std::unique_ptr<System>> systems_;
  std::vector<Attachment> attachments_;
  int next_id_ = 0;
  int next_attachment_ = 0;
  StepStats stats_;
  btInternalTickCallback chained_ = nullptr;  // the application's pre-tick callback, run first
  bool pre_solved_ = false;  // pre_solve ran in the current internal step
  std::vector<Residual> residuals_;  // applied by the next updateAction
  std::vector<Predicted> predicted_;  // Bullet's contact accelerations of the last step
  std::vector<SystemId> callback_ids_;  // scratch: systems with a step callback
  std::vector<const btCollisionObject*> live_;  // scratch: the world's objects, sorted
  // Ends the attachments (and forgets the predictions) of bodies that have
  // left the world; run at the start of every step.
  void drop_departed_bodies();
  // Scratch, reused across steps.
  std::vector<const btCollisionObject*> candidates_;
  std::vector<const btCollisionObject*> by_motion_;  // of candidates_: found by their motion only
  std::vector<const btCollisionObject*> refresh_candidates_;  // refresh_contacts' own
  // refresh_contacts' scratch: contact index by (particle, body) (pair_key).
  std::unordered_map<std::uint64_t, std::size_t> refresh_pairs_;
  static std::uint64_t pair_key(xpbd::Index particle, xpbd::Index body) {
    return (std::uint64_t(std::uint32_t(particle)) << 32) | std::uint32_t(body);
  }
  std::vector<Shadow> shadows_;  // bodies touched in the current internal step
  std::vector<xpbd::Vec3> features_;  // scratch: feature points of one body (body frame)
  std::vector<xpbd::Vec3> tri_lo_, tri_hi_;  // scratch: swept triangle bounds
  std::vector<xpbd::Vec3> sweep_lo_, sweep_hi_;  // scratch: each particle's box over the step
  std::vector<btPersistentManifold*> spacers_;  // this step's spacer manifolds (world_spacers.cpp)
  std::vector<std::pair<xpbd::Index, std::size_t>> spacer_order_;  // scratch: (particle, contact)
  std::vector<char> settle_moved_, settle_next_;  // scratch: particles moved in a settle round
};

}  // namespace xpbd_bullet
