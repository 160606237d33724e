#pragma once
#include <algorithm>
// XpbdWorld's private state, shared by world.cpp (lifecycle, hook, hand-over
// to Bullet) and world_contacts.cpp (shadow bodies, contact search, the
// XPBD step of one system). Internal to the bridge.
#include <btBulletDynamicsCommon.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "box_list.hpp"
#include "pair_culling.hpp"
#include "triangle_bvh.hpp"
#include "triangle_grid.hpp"
#include "xpbd/rigid.hpp"
#include "xpbd_bullet/narrowphase.hpp"
#include "xpbd_bullet/world.hpp"

namespace xpbd_bullet {

using xpbd::Index;
using xpbd::Quat;
using xpbd::Real;
using xpbd::Vec3;

inline Vec3 to_vec(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }
inline btVector3 to_bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
inline Quat to_quat(const btQuaternion& q) { return Quat(q.w(), q.x(), q.y(), q.z()); }
inline btQuaternion to_bt(const Quat& q) { return btQuaternion(q.x(), q.y(), q.z(), q.w()); }

// True if o's pose (and, for a rigid body, its velocities) are finite: a body
// that is not is left out of the systems' steps (StepStats::skipped_bodies).
inline bool finite_body(const btCollisionObject* o) {
  const btTransform& t = o->getWorldTransform();
  bool ok = std::isfinite(t.getOrigin().x()) && std::isfinite(t.getOrigin().y()) &&
            std::isfinite(t.getOrigin().z());
  for (int r = 0; r < 3 && ok; ++r)
    ok = std::isfinite(t.getBasis()[r].x()) && std::isfinite(t.getBasis()[r].y()) &&
         std::isfinite(t.getBasis()[r].z());
  if (const btRigidBody* rb = btRigidBody::upcast(o); rb && ok) {
    const btVector3 v = rb->getLinearVelocity(), w = rb->getAngularVelocity();
    ok = std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()) && std::isfinite(w.x()) &&
         std::isfinite(w.y()) && std::isfinite(w.z());
  }
  return ok;
}

// True if every particle position and velocity of st is finite.
inline bool all_finite(const xpbd::State& st) {
  for (std::size_t i = 0; i < st.x.size(); ++i)
    if (!st.x[i].allFinite() || !st.v[i].allFinite()) return false;
  return true;
}

// True if o is in w's object array (bodies can be removed between steps).
inline bool in_world(const btCollisionWorld& w, const btCollisionObject* o) {
  const int i = o->getWorldArrayIndex();
  const auto& arr = w.getCollisionObjectArray();
  return i >= 0 && i < arr.size() && arr[i] == o;
}

namespace detail {

// Adds to `out` (the broadphase's candidates for the box lo..hi) every
// moving rigid body (dynamic or kinematic) that the filters let through and
// whose AABB, grown by its travel over dt (speed, the acceleration of its
// applied forces, and its rotation times its AABB's diagonal), overlaps the
// box, if not listed already. The broadphase knows each body at its pose
// only: a body faster than its size per step reaches particles its box at
// the step's start is far from (narrowphase.cpp).
void add_moving_candidates(btCollisionWorld& world, const Vec3& lo, const Vec3& hi, Real dt, int filter_group,
                           int filter_mask, std::vector<const btCollisionObject*>& out);

// Appends the sharp feature points of a shape in the frame `t` (the body's
// frame for t = identity): box corners and points along box edges no more
// than `spacing` apart (if `edges`; the feature-triangle search asks for
// them without ContactSettings::edge_contacts, or for a fast body), the
// vertices of other polyhedral shapes (hulls), recursively for compounds. Smooth shapes (sphere,
// capsule, cylinder, cone) and meshes have none. centres (if given) gets,
// for each feature, a point inside the convex shape it belongs to (the
// mean of its vertices; a compound's child's own). world_triangle_contacts.cpp.
void collect_features(const btCollisionShape& shape, const btTransform& t, Real spacing, std::vector<Vec3>& out,
                      bool edges = true, std::vector<Vec3>* centres = nullptr);

// Whether collect_features or collect_mesh_features can give obj any
// feature: a polyhedral shape (or a compound with one), or a static or
// kinematic triangle mesh. world_triangle_contacts.cpp.
bool may_have_features(const btCollisionObject& obj);

// Appends the features of a triangle mesh (its own frame) among its
// triangles that overlap the box lo..hi (the same frame): each corner of a
// sharp edge once, and points along the edge no more than `spacing` apart.
// An edge is sharp where its two triangles are more than about a degree
// from flat (ridge or valley), or where it has one triangle or more than
// two. tris: scratch. world_triangle_contacts.cpp.
void collect_mesh_features(const btConcaveShape& shape, const Vec3& lo, const Vec3& hi, Real spacing,
                           std::vector<std::array<Vec3, 3>>& tris, std::vector<Vec3>& out);

// A dynamic body about to be coupled without a prediction of Bullet's
// contacts on it (its first coupled step): the probe fills accel and
// ang_accel with what Bullet's contacts put on it when it is held fixed,
// over its mass and dt (world_probe.cpp). skip_static leaves out its
// contacts with static bodies, which XPBD solves itself
// (SystemSettings::coupled_static_contacts).
struct ProbeLoad {
  btRigidBody* body = nullptr;
  bool skip_static = false;
  btVector3 accel{0, 0, 0}, ang_accel{0, 0, 0};
};
// Runs collision detection, then Bullet's solver once with the bodies held
// fixed, and puts back everything the solve wrote (world_probe.cpp).
void probe_loads(btDiscreteDynamicsWorld& world, std::vector<ProbeLoad>& bodies, btScalar dt);

// True for the shapes query_point answers in closed form in their own
// frame: sphere, box, capsule, cylinder, plane (not a compound).
bool is_primitive(const btCollisionShape& shape);
// query_point's answer for such a shape at p in the shape's own frame,
// with point and normal in that frame (narrowphase.cpp).
bool query_primitive_local(const btCollisionShape& shape, const Vec3& p, Real max_distance, ParticleContact& out);

// The narrowphase of one particle against obj: x is the particle at the
// pose Bullet's shape is at, `motion` its motion relative to the body over
// the time the contact covers, `travel` a bound on that motion's length.
// Fast relative motion (travel > margin): the first surface crossed on the
// way; otherwise (or if none is crossed) the closest surface within reach.
// A particle whose path crosses no surface and that is not within reach
// at the start, but whose motion ends outside the surface and within
// `ahead` of it, gets the contact of the closest surface at the motion's
// end. The caller's `ahead` is the particle's radius, the thickness and the
// margin (the contact is needed once the particle comes that near, not
// only where it would cross), plus how far the body's acceleration may
// carry it beyond its straight motion. Without it a body falling onto a
// cloth from farther than the margin, whose straight motion ended just
// short of the particles' centres, got no contact in the step that carried
// it into the cloth, and the next step pushed it out at the overlap within
// a substep: a 2 kg bar landing on one end at 4.25 m/s left at 4.22 m/s
// (docs/squeeze-surface-edges.md). The body's turning is not added.
// The end's closest surface is taken only where the motion heads into it
// within about 26 degrees of its normal (a face coming at the particle):
// the straight motion leaves out the body's turning, and from a glancing
// approach the closest feature at the end (a turning box's edge) is not the
// one the particle meets. Taken for any approach, a diagonal edge contact
// under the same 1000 kg box stretched the cloth by 0.20 and 0.60 (0.15 and
// 0.17 without it; test_world_penetration_tolerance.cpp).
inline constexpr Real kHeadOn = Real(0.9);
inline bool particle_query(const btCollisionObject& obj, const Vec3& x, const Vec3& motion, Real travel,
                           Real reach, Real ahead, Real margin, ParticleContact& c) {
  Real frac;
  if (travel > margin && sweep_point(obj, x, x + motion, c, frac)) return true;
  if (query_point(obj, x, reach, c)) return true;
  return travel > margin && query_point(obj, x + motion, ahead, c) && c.distance >= Real(0) &&
         c.normal.dot(motion) <= -kHeadOn * motion.norm();
}

// The contact of `particle` with State::bodies[body] (obj) from the
// narrowphase's c in the body's frame; thick: the particle's radius plus
// the thickness.
inline xpbd::BodyContact body_contact_local(const ContactSettings& cs, const btCollisionObject& obj, Index particle,
                                            Index body, Real thick, const ParticleContact& c) {
  xpbd::BodyContact bc;
  bc.particle = particle;
  bc.body = body;
  bc.r = c.point;
  bc.n = c.normal;
  bc.thickness = thick;
  bc.static_friction = cs.static_friction * obj.getFriction();
  bc.dynamic_friction = cs.dynamic_friction * obj.getFriction();
  bc.restitution = cs.restitution * obj.getRestitution();
  bc.compliance = cs.compliance;
  return bc;
}

// The same from c in world coordinates, at the pose `pose_inv` inverts.
inline xpbd::BodyContact body_contact(const ContactSettings& cs, const btCollisionObject& obj, Index particle,
                                      Index body, Real thick, const btTransform& pose_inv,
                                      const ParticleContact& c) {
  return body_contact_local(cs, obj, particle, body, thick,
                            {to_vec(pose_inv * to_bt(c.point)), to_vec(pose_inv.getBasis() * to_bt(c.normal)), c.distance});
}

}  // namespace detail

// One rigid body seen during the current internal step (XpbdWorld::pre_solve,
// before Bullet's collision detection and solver).
struct XpbdWorld::Shadow {
  const btCollisionObject* obj = nullptr;
  btRigidBody* dynamic = nullptr;  // set if the body is dynamic (receives the hand-over)
  // Where Bullet's collision shape is while XPBD runs: a dynamic or static
  // body's pose at the start of the step; a kinematic body's target, the pose
  // at the end of the step (Bullet moves kinematic bodies before its
  // internal steps).
  btTransform pose;
  btTransform start;         // the body's pose at the start of the step
  btTransform start_to_pose; // world points at `start` -> the same body points at `pose`
  // Velocities at the start of the step (a dynamic body's after Bullet's
  // damping of this step), and its accelerations over the step: its forces
  // over its mass plus contact_accel (and the angular ones likewise).
  Vec3 v = Vec3::Zero(), w = Vec3::Zero();
  Vec3 accel = Vec3::Zero(), ang_accel = Vec3::Zero();
  // The part of accel predicted for Bullet's own contacts and joints: what
  // they did to the body in the previous step, per unit time.
  Vec3 contact_accel = Vec3::Zero(), contact_ang_accel = Vec3::Zero();
  xpbd::RigidBody initial;  // the xpbd shadow at the start of the step
  // Filled by the systems that step it (dynamic bodies only):
  bool coupled = false;     // some system has it in State::bodies
  // Some system solved its contacts with static bodies inside the substeps
  // (State::world_contacts): Bullet's impulses on those contacts are then
  // left out of the next step's prediction (XpbdWorld::Predicted).
  bool world_contacts = false;
  xpbd::RigidBody free;     // the first such system's contact-free end state
  int substeps = 1;         // that system's substeps per step
  Vec3 dv = Vec3::Zero(), dw = Vec3::Zero(), dx = Vec3::Zero();  // summed changes
  Quat dq = Quat::Identity();
};

// What the contact search found for one candidate (body -1 until joined).
struct XpbdWorld::CandidateContacts {
  std::vector<xpbd::BodyContact> particle;
  std::vector<xpbd::BodyTriangleContact> triangle;
  std::vector<xpbd::BodyEdgeContact> edge;
  int queries = 0;  // StepStats::queries
  int swept = 0;    // StepStats::swept_triangle_contacts
  int capped = 0;   // StepStats::capped_features
  void clear() {
    particle.clear();
    triangle.clear();
    edge.clear();
    queries = swept = capped = 0;
  }
};

// One thread's scratch of the feature-triangle search, reused across steps.
struct XpbdWorld::FeatureScratch {
  std::vector<Vec3> features;                  // a body's feature points (body frame)
  std::vector<Vec3> centres;                   // a point inside each feature's shape (body frame)
  std::vector<std::array<Vec3, 3>> mesh_tris;  // a mesh's triangles near the system
  std::vector<Vec3> feature_at;                // the features at the step's start (world)
  std::vector<Real> feature_travel;            // and how far each can move over the step
  std::vector<btTransform> path_tf;            // a fast body's poses along the step
  std::vector<int> body_tris, tri_found;       // triangles the hierarchy returned (body, feature)
  std::vector<std::uint64_t> tri_marks;        // scratch of the hierarchy's queries (all zero between them)
  detail::TriangleGrid grid;                   // the body's triangles near its features
  detail::BoxList boxes;                       // the boxes of body_tris, by coordinate
  std::vector<std::array<Vec3, 3>> box_edges;  // a body's box edges: ends, outward bisector (body frame)
  std::vector<unsigned> edge_stamp;            // per surface edge: the last body call that took it
  std::vector<int> near_edges;                 // surface edges e near the body as 2 e + held, ascending
  std::vector<std::array<xpbd::Index, 2>> near_pairs;  // soft edges near the body, in test order
  std::vector<std::uint8_t> near_held;         // and whether each is held (edge_contacts_of)
  std::vector<Vec3> edge_lo, edge_hi;          // their boxes over the step
  detail::BoxList edge_boxes;                  // the same, by coordinate
  std::vector<int> edge_found;                 // positions in near_pairs whose box meets a box edge's
  unsigned stamp = 0;
};

namespace detail {

// The edges of triangles `tris`, each once (lower index first, in order of
// first appearance), each triangle's three edges as indices into them
// (side i: corners i and i + 1), and per triangle, bit i set if side i is
// its edge's first appearance (world_edge_contacts.cpp).
void find_soft_edges(const std::vector<std::array<xpbd::Index, 3>>& tris, std::vector<std::array<xpbd::Index, 2>>& edges,
                     std::vector<std::array<int, 3>>& tri_edges, std::vector<std::uint8_t>& tri_owns);

// A system without collision triangles: its surface triangles' edges as
// soft edges, and each particle's (System::edge_begin, edges_at); made
// once (world_edge_contacts.cpp).
void surface_edges(const xpbd::Model& m, std::vector<std::array<xpbd::Index, 2>>& edges,
                   std::vector<std::array<int, 3>>& tri_edges, std::vector<std::uint8_t>& tri_owns,
                   std::vector<int>& edge_begin, std::vector<int>& edges_at);

// True if `shape` is a box or a compound holding one (the shapes whose
// edges edge_contacts_of tests).
bool has_box_edges(const btCollisionShape& shape);

// The box of soft edge (p0, p1) over the step: both ends at the start and
// at x + dt v, grown by the larger radius, the thickness and the margin.
Box soft_edge_box(const xpbd::Model& m, const xpbd::State& st, xpbd::Index p0, xpbd::Index p1, Real dt,
                  Real thickness, Real margin);

// Widens the culling's half sizes (ContactScratch::half, r_i + thickness +
// margin + dt |v_i|) so that each particle's cube holds the box
// (soft_edge_box) of every soft edge at it: half_i += max over its edges
// (i, j) of |x_j - x_i| + dt |v_j| + max(r_j - r_i, 0). Then a soft edge
// whose box meets a candidate's box has both ends in the candidate's
// culled particles (if movable), and edge_contacts_of finds from them the
// same edges as from every particle. reach: scratch.
void widen_for_edges(const xpbd::Model& m, const xpbd::State& st, Real dt,
                     const std::vector<std::array<xpbd::Index, 2>>& edges, std::vector<Real>& reach,
                     std::vector<Real>& half);

// Calls f(k, slot) once for every k in [0, count): on the calling thread in
// order without a pool (or with one thread, or one item), else on up to
// `slots` of the pool's threads, each taking the next k as it is free
// (candidates differ much in cost). slot in [0, slots) names the thread's
// scratch; no two threads run under one slot at a time.
template <class F>
void for_each_candidate(xpbd::Workers* workers, std::size_t count, int slots, F&& f) {
  if (workers == nullptr || slots < 2 || count < 2) {
    for (std::size_t k = 0; k < count; ++k) f(k, 0);
    return;
  }
  std::atomic<std::size_t> next{0};
  workers->run(slots, [&](int slot) {
    for (std::size_t k = next.fetch_add(1, std::memory_order_relaxed); k < count;
         k = next.fetch_add(1, std::memory_order_relaxed))
      f(k, slot);
  });
}

// Calls f(begin, end, piece) for the pieces [begin, end) of [0, count),
// `chunk` items each (the last one shorter), piece = begin / chunk: all on
// the calling thread as one piece (0, count, 0) without a pool (or with one
// thread, or a single piece), else one task per piece on the pool.
template <class F>
void for_each_chunk(xpbd::Workers* workers, std::size_t count, std::size_t chunk, F&& f) {
  const std::size_t pieces = (count + chunk - 1) / chunk;
  if (workers == nullptr || workers->threads() < 2 || pieces < 2) {
    if (count > 0) f(std::size_t(0), count, std::size_t(0));
    return;
  }
  workers->run(static_cast<int>(pieces), [&](int p) {
    const std::size_t b = std::size_t(p) * chunk;
    f(b, std::min(count, b + chunk), std::size_t(p));
  });
}

}  // namespace detail

struct XpbdWorld::System {
  int id = 0;
  std::shared_ptr<const xpbd::Model> model;
  std::shared_ptr<xpbd::Model> own_model;  // set by the first set_material: then model == own_model
  xpbd::State state;
  SystemSettings settings;
  std::string error;                // set when a step failed; the system is no longer stepped
  std::vector<int> shadow_of_body;  // per State::bodies entry: index into shadows_
  std::vector<xpbd::RigidBody> free_bodies;  // scratch: bodies moved without contacts
  detail::ContactScratch contact;            // scratch of the contact search
  std::vector<CandidateContacts> found;      // scratch: per candidate, what the search found
  // scratch: where each candidate's contacts start in the state's lists
  // (particle, triangle, edge), and one past the last candidate's
  std::vector<std::array<std::size_t, 3>> found_at;
  std::vector<FeatureScratch> feature_scratch;  // scratch: per thread of the search
  std::unique_ptr<detail::TriangleBvh> tri_bvh;  // ContactSettings::triangle_bvh_from; made on first use
  // The collision triangles' edges, each once, and each triangle's three
  // (indices into soft_edges); made on first use (triangle_bounds). A
  // system without collision triangles takes its surface triangles' edges
  // instead (surface_edges), and each particle's edges:
  // soft_edges[edges_at[edge_begin[i] .. edge_begin[i + 1])].
  std::vector<std::array<xpbd::Index, 2>> soft_edges;
  std::vector<std::array<int, 3>> tri_edges;
  std::vector<std::uint8_t> tri_owns;  // per triangle: its sides that are their edge's first (find_soft_edges)
  std::vector<int> edge_begin, edges_at;
  std::vector<Real> edge_reach;  // scratch of detail::widen_for_edges
  std::vector<BodyContactReport> report;     // contact_report(id): the last step's
  StepCallback callback;                     // set_step_callback(id)
  bool stepped = false;                      // stepped in the current internal step
  // Sleeping (SystemSettings::sleep_speed, world_sleep.cpp).
  bool asleep = false;
  Real quiet = 0;                            // s, time every particle has been slower than sleep_speed
  Vec3 box_lo = Vec3::Zero(), box_hi = Vec3::Zero();  // m, the box that wakes it (set when it falls asleep)
  std::vector<Vec3> pins_asleep;             // State::pin_target when it fell asleep
  // Divergence checks (world_health.cpp).
  SystemHealth health;
  xpbd::HealthObservation observed;  // kinetic0, potential0 from the first step; potential_min so far
  bool observed_started = false;
  double energy_end = 0;   // J, kinetic + potential energy after the last step
  double edits_input = 0;  // J, energy the application added between steps, summed
  double touch_input = 0;  // J, the most a body or pin could give in one step (2 M v^2)
  std::vector<Vec3> health_pins;  // State::pin_target at the last step
  // kg per particle, 1 / Model::inv_mass (0: kinematic), taken once: the
  // inverse masses are fixed after compile (set_material keeps them).
  std::vector<double> health_mass;
  // The tolerance's controller (SystemSettings::tolerance, world_contacts.cpp).
  int tol_substeps = 0;  // substeps for the next step (0: start from SystemSettings::substeps)
  int tol_calm = 0;      // steps in a row that could have taken fewer substeps
  double tol_window_max = 0;  // largest error (relative to the tolerance) over those steps
  // A rise that did not pay (world_contacts.cpp): the error it left, and for
  // how many more steps an error up to kTolFutileGrowth times it is not
  // solved again.
  double tol_futile_error = 0;
  int tol_futile_steps = 0;
  int step_substeps = 0;  // substeps of the step being solved (settings' or the tolerance's)
  xpbd::State tol_saved;  // the state before the solve, for solving the step again
};

// Who a body is, beyond its address (which a deleted body's successor may
// reuse): the broadphase proxy it got when it was added to the world, and
// that proxy's unique id. A body removed from the world and added again (or
// a new body at a reused address) has another.
struct BodyIdentity {
  const btCollisionObject* obj = nullptr;
  const btBroadphaseProxy* proxy = nullptr;
  int uid = -1;
  static BodyIdentity of(const btCollisionObject* o) {
    const btBroadphaseProxy* p = o->getBroadphaseHandle();
    return {o, p, p ? p->m_uniqueId : -1};
  }
  // `live`: the world's objects, sorted; the body is dereferenced only if
  // its address is among them.
  bool alive(const std::vector<const btCollisionObject*>& live) const {
    if (!std::binary_search(live.begin(), live.end(), obj)) return false;
    const btBroadphaseProxy* p = obj->getBroadphaseHandle();
    return p == proxy && p != nullptr && p->m_uniqueId == uid;
  }
};

struct XpbdWorld::Attachment {
  int id = 0;
  int system = 0;
  Index particle = 0;
  btRigidBody* body = nullptr;
  btVector3 local;
  Real compliance = 0;
  BodyIdentity identity;  // body when attached
};

// What the hand-over expects of Bullet's step for one coupled body, and
// what updateAction adds after Bullet's integration.
//
// The shadow ends at (x_end, q_end) with velocities (v_end, w_end). If
// Bullet's contacts and joints change the body's velocity exactly as
// predicted (contact_accel dt), Bullet ends with v_end, and its integration
// reaches x0 + dt v_end: the residual is then the XPBD path's excess over
// that, x_end - x0 - dt v_end (zero at rest), and the same for the rotation.
// Where Bullet's contacts do something else, by dv_b = v_bullet - v_end, that
// change is taken as acting uniformly over the step, as a force inside the
// substeps would: it moves the body by dv_b dt (n+1)/(2n) rather than the
// dv_b dt of Bullet's integration, so the residual has -dv_b dt (n-1)/(2n)
// more (the same for the rotation vector).
struct XpbdWorld::Residual {
  btRigidBody* body = nullptr;
  btVector3 dx;             // m, the XPBD path's excess (translation)
  btQuaternion dq;          // its rotation, applied on the left
  btVector3 v_end, w_end;   // m/s, rad/s, the shadow's end velocities
  btVector3 v_pre, w_pre;   // velocities Bullet reaches before its contacts: keep u + kick
  btScalar spread = 0;      // s, dt (n-1)/(2n)
  bool world_contacts = false;  // Shadow::world_contacts
  // The body's flags before the step: its gyroscopic flags are off while
  // Bullet steps it (XPBD's substeps integrate that term; hand_over).
  int flags = 0;
};

// Bullet's contact and joint acceleration on a coupled body in the last
// step, (v_bullet - v_pre)/dt: fed to the body's shadow in the next step.
// Where XPBD solved the body's contacts with static bodies itself
// (Shadow::world_contacts), the impulses Bullet's solver put on those
// contacts are taken out: the support is then counted once, by XPBD's
// contacts, instead of also lifting the shadow's weight through accel (a
// shadow that carries the predicted support of the ground feels no gravity
// inside XPBD, and anything that pushes it up lifts it).
struct XpbdWorld::Predicted {
  const btRigidBody* body = nullptr;
  BodyIdentity identity;
  Vec3 accel = Vec3::Zero(), ang_accel = Vec3::Zero();
};

}  // namespace xpbd_bullet
