#include "xpbd_bullet/world.hpp"

#include <LinearMath/btTransformUtil.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "xpbd/error.hpp"
#include "xpbd/rigid_solve.hpp"
#include "xpbd/spatial_hash.hpp"
#include "xpbd_bullet/narrowphase.hpp"

namespace xpbd_bullet {

using xpbd::Index;
using xpbd::Quat;
using xpbd::Real;
using xpbd::Vec3;

namespace {

Vec3 to_vec(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }
btVector3 to_bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
Quat to_quat(const btQuaternion& q) { return Quat(q.w(), q.x(), q.y(), q.z()); }
btQuaternion to_bt(const Quat& q) { return btQuaternion(q.x(), q.y(), q.z(), q.w()); }

void check_settings(const SystemSettings& s) {
  auto bad = [](const std::string& field, const std::string& what) {
    throw xpbd::ConfigError("SystemSettings." + field + ": " + what);
  };
  if (s.substeps < 1) bad("substeps", "must be >= 1, got " + std::to_string(s.substeps));
  if (s.iterations < 1) bad("iterations", "must be >= 1, got " + std::to_string(s.iterations));
  const ContactSettings& c = s.contacts;
  auto nonneg = [&](const char* f, Real v) {
    if (!(v >= Real(0)) || !std::isfinite(v))
      bad(std::string("contacts.") + f, "must be finite and >= 0, got " + std::to_string(v));
  };
  nonneg("margin", c.margin);
  nonneg("thickness", c.thickness);
  nonneg("static_friction", c.static_friction);
  nonneg("dynamic_friction", c.dynamic_friction);
  nonneg("restitution", c.restitution);
  nonneg("compliance", c.compliance);
  if (!(c.feature_spacing > Real(0)) || !std::isfinite(c.feature_spacing))
    bad("contacts.feature_spacing", "must be finite and > 0, got " + std::to_string(c.feature_spacing));
  if (c.restitution > Real(1)) bad("contacts.restitution", "must be <= 1, got " + std::to_string(c.restitution));
}

bool in_world(const btCollisionWorld& w, const btCollisionObject* o) {
  const int i = o->getWorldArrayIndex();
  const auto& arr = w.getCollisionObjectArray();
  return i >= 0 && i < arr.size() && arr[i] == o;
}

// Sharp feature points of a shape in the frame `t` (body frame): box corners
// and points along box edges no more than `spacing` apart, the vertices of
// other polyhedral shapes (hulls), recursively for compounds. Smooth shapes
// (sphere, capsule, cylinder, cone) and meshes have none.
void collect_features(const btCollisionShape& shape, const btTransform& t, Real spacing,
                      std::vector<Vec3>& out) {
  if (shape.isCompound()) {
    const auto& c = static_cast<const btCompoundShape&>(shape);
    for (int i = 0; i < c.getNumChildShapes(); ++i)
      collect_features(*c.getChildShape(i), t * c.getChildTransform(i), spacing, out);
    return;
  }
  if (!shape.isPolyhedral()) return;
  const auto& p = static_cast<const btPolyhedralConvexShape&>(shape);
  for (int i = 0; i < p.getNumVertices(); ++i) {
    btVector3 v;
    p.getVertex(i, v);
    out.push_back(to_vec(t * v));
  }
  if (shape.getShapeType() != BOX_SHAPE_PROXYTYPE) return;
  for (int i = 0; i < p.getNumEdges(); ++i) {
    btVector3 a, b;
    p.getEdge(i, a, b);
    const Vec3 pa = to_vec(t * a), pb = to_vec(t * b);
    const int pieces = static_cast<int>(std::ceil((pb - pa).norm() / spacing));
    for (int k = 1; k < pieces; ++k) out.push_back(pa + (Real(k) / Real(pieces)) * (pb - pa));
  }
}


// ---------------------------------------------------------------------------
// Culling of (particle, body) pairs before the narrowphase.
//
// The narrowphase reports a contact for particle i and body b only if the
// particle's centre comes within reach_i = r_i + thickness + margin + travel_i
// of b's surface, travel_i = dt (|v_i - v_b| + w_b extent_b) (step_system):
// query_point() finds nothing farther than reach_i, and a sweep hit lies on
// the surface within dt |v_i - v_b| <= travel_i of the start point. The
// particle is tested relative to the body's start pose (moved to its end
// pose, where the rigid transform keeps distances), and the body's shape at
// the start pose lies inside its AABB there (Bullet's getAabb, the box the
// broadphase itself relies on). So a contact needs
//   dist(x_i, AABB_b) <= reach_i <= half_i + grow_b, with
//   half_i = r_i + thickness + margin + dt |v_i|  and
//   grow_b = dt (|v_b| + w_b extent_b)            (|v_i - v_b| <= |v_i| + |v_b|),
// and then the cube of half size half_i around x_i overlaps AABB_b grown by
// grow_b (an L-infinity distance never exceeds the Euclidean one). A pair
// whose boxes are apart is skipped; the others go to the narrowphase as
// before, in the same order, so the contacts are the same. grow_b also holds
// a slack of 4 kDegenerateRel relative to the coordinates, for the round-off
// of the transforms and of the narrowphase's own tolerances (at most
// kDegenerateRel relative).
//
// Finding the overlapping boxes: the candidate boxes go into a uniform grid
// (hashed cells, as xpbd/spatial_hash.hpp), each into every cell its box
// grown by grid_reach covers; a particle with half_i <= grid_reach then looks
// at the one cell of its centre only. grid_reach is twice the mean half_i,
// so in a scene that moves as a whole every particle is looked up that way;
// a faster particle, and a candidate box that covers more than kMaxCells
// cells (a ground plane), is tested against all boxes of the other kind. The
// cell size is the median side of the grown candidate boxes (any size is
// correct; this one puts a typical body in about 2 x 2 x 2 cells). Work per
// step: O(n + candidates + pairs), plus n x (wide candidates) box tests.

constexpr std::int64_t kMaxCells = 512;  // cells one candidate box may cover in the grid

// Axis-aligned box (m, world).
struct Box {
  Vec3 lo, hi;
};

// False only if the cube of half size `half` (m) around c and the box are
// apart on an axis. A NaN makes every comparison false, so a pair with a NaN
// is never skipped (query_point then reports the bad input, as without
// culling).
bool overlaps(const Vec3& c, Real half, const Box& b) {
  for (int a = 0; a < 3; ++a)
    if (c[a] + half < b.lo[a] || c[a] - half > b.hi[a]) return false;
  return true;
}

// One broadphase candidate of the current step, as the contact loop uses it.
struct Candidate {
  const btCollisionObject* obj = nullptr;
  btTransform to_end;      // its shadow's end_to_start_frame
  btTransform end_inv;     // inverse of its end pose
  Vec3 vb = Vec3::Zero();  // m/s, linear velocity
  Real wb = 0;             // rad/s, angular speed
  Real extent = 0;         // m, diagonal of its AABB at the end pose
  Box box;                 // m, its AABB at the start pose grown by grow_b
  bool in_grid = false;
};

struct GridEntry {
  xpbd::Cell cell;
  Index candidate = 0;
};

// Per-system scratch of the contact search, reused across steps: it only
// grows (std::vector keeps its capacity through clear/assign/resize).
struct ContactScratch {
  std::vector<Candidate> candidates;
  std::vector<Real> half;              // m, per particle: half_i
  std::vector<Real> sides;             // m, scratch for the median cell size
  std::vector<GridEntry> entries;      // (cell, candidate) in insertion order
  std::vector<GridEntry> grid;         // the same, grouped by bucket
  std::vector<Index> bucket_begin;     // 2^k + 1 offsets into grid
  std::vector<Index> wide;             // candidates not in the grid
  std::vector<std::array<Index, 2>> found;  // (candidate, particle), particles increasing
  std::vector<Index> pair_begin;       // per candidate + 1: offsets into particles
  std::vector<Index> particles;        // particles of each candidate, increasing
};

// Fills sc.pair_begin / sc.particles: for every candidate k, the movable
// particles i, in increasing order, whose cube [x_i - half_i, x_i + half_i]
// overlaps candidates[k].box. The grid only finds them faster: the result is
// exactly that box test over all pairs.
void find_pairs(const std::vector<Vec3>& x, const std::vector<Real>& inv_mass, ContactScratch& sc) {
  using xpbd::Cell;
  namespace hd = xpbd::detail;
  const std::size_t n = x.size();
  const std::size_t nc = sc.candidates.size();

  // grid_reach: twice the mean half size (finite ones) of the movable particles.
  Real sum = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (inv_mass[i] != Real(0) && std::isfinite(sc.half[i])) sum += sc.half[i], ++count;
  const Real grid_reach = count > 0 ? Real(2) * sum / Real(count) : Real(0);

  // Cell size: the median largest side of the candidate boxes grown by grid_reach.
  sc.sides.clear();
  for (const Candidate& c : sc.candidates)
    if (c.box.lo.allFinite() && c.box.hi.allFinite())
      sc.sides.push_back((c.box.hi - c.box.lo).maxCoeff() + Real(2) * grid_reach);
  Real cell = 1;
  if (!sc.sides.empty()) {
    const auto mid = sc.sides.begin() + std::ptrdiff_t(sc.sides.size() / 2);
    std::nth_element(sc.sides.begin(), mid, sc.sides.end());
    cell = *mid;
  }
  if (!(cell > Real(0)) || !std::isfinite(cell)) cell = 1;  // m; any positive size is correct
  const Real inv_cell = Real(1) / cell;

  // Candidates into the cells of their box grown by grid_reach (plus a
  // round-off allowance for x_i +- half_i). cell_at is monotone, so a centre
  // x_i with half_i <= grid_reach whose cube overlaps the box lies in one of
  // those cells.
  sc.entries.clear();
  sc.wide.clear();
  for (std::size_t k = 0; k < nc; ++k) {
    Candidate& c = sc.candidates[k];
    c.in_grid = false;
    if (c.box.lo.allFinite() && c.box.hi.allFinite()) {
      const Real scale = std::max(c.box.lo.cwiseAbs().maxCoeff(), c.box.hi.cwiseAbs().maxCoeff());
      const Real grow =
          grid_reach + Real(4) * xpbd::kDegenerateRel * (Real(1) + grid_reach + scale);
      const Cell lo = hd::cell_at(c.box.lo.array() - grow, inv_cell);
      const Cell hi = hd::cell_at(c.box.hi.array() + grow, inv_cell);
      // Cells covered, stopping before the product can overflow (each
      // factor is at most 2^31 + 1).
      std::int64_t cells = 1;
      for (int a = 0; a < 3 && cells <= kMaxCells; ++a)
        cells *= std::int64_t(hi[a]) - std::int64_t(lo[a]) + 1;
      if (cells <= kMaxCells) {
        Cell q;
        for (q[2] = lo[2]; q[2] <= hi[2]; ++q[2])
          for (q[1] = lo[1]; q[1] <= hi[1]; ++q[1])
            for (q[0] = lo[0]; q[0] <= hi[0]; ++q[0]) sc.entries.push_back({q, Index(k)});
        c.in_grid = true;
      }
    }
    if (!c.in_grid) sc.wide.push_back(Index(k));
  }

  // Hash table of 2^k >= 2 entries buckets, filled by a counting sort.
  const std::size_t table = std::bit_ceil(std::max<std::size_t>(2 * sc.entries.size(), 1));
  const auto mask = static_cast<std::uint32_t>(table - 1);
  sc.bucket_begin.assign(table + 1, 0);
  for (const GridEntry& e : sc.entries) ++sc.bucket_begin[hd::bucket_of(e.cell, mask) + 1];
  for (std::size_t b = 0; b < table; ++b) sc.bucket_begin[b + 1] += sc.bucket_begin[b];
  sc.grid.resize(sc.entries.size());
  for (const GridEntry& e : sc.entries) sc.grid[std::size_t(sc.bucket_begin[hd::bucket_of(e.cell, mask)]++)] = e;
  for (std::size_t b = table; b > 0; --b) sc.bucket_begin[b] = sc.bucket_begin[b - 1];
  sc.bucket_begin[0] = 0;

  // Overlapping pairs, particle by particle in increasing order.
  sc.found.clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (inv_mass[i] == Real(0)) continue;  // never gets a contact
    const Vec3& xi = x[i];
    const Real h = sc.half[i];
    auto test = [&](Index k) {
      if (overlaps(xi, h, sc.candidates[std::size_t(k)].box)) sc.found.push_back({k, Index(i)});
    };
    if (h <= grid_reach && xi.allFinite()) {  // false for a NaN half size: tested against all
      const Cell q = hd::cell_at(xi, inv_cell);
      const std::uint32_t b = hd::bucket_of(q, mask);
      for (Index e = sc.bucket_begin[b]; e < sc.bucket_begin[b + 1]; ++e)
        if (hd::same_cell(sc.grid[std::size_t(e)].cell, q)) test(sc.grid[std::size_t(e)].candidate);
      for (Index k : sc.wide) test(k);
    } else {
      for (std::size_t k = 0; k < nc; ++k) test(Index(k));
    }
  }

  // Grouped by candidate (a stable counting sort keeps the particles increasing).
  sc.pair_begin.assign(nc + 1, 0);
  for (const auto& f : sc.found) ++sc.pair_begin[std::size_t(f[0]) + 1];
  for (std::size_t k = 0; k < nc; ++k) sc.pair_begin[k + 1] += sc.pair_begin[k];
  sc.particles.resize(sc.found.size());
  for (const auto& f : sc.found) sc.particles[std::size_t(sc.pair_begin[std::size_t(f[0])]++)] = f[1];
  for (std::size_t k = nc; k > 0; --k) sc.pair_begin[k] = sc.pair_begin[k - 1];
  sc.pair_begin[0] = 0;
}

}  // namespace

// One rigid body touched during the current internal step: its Bullet state
// at the end of the step (after Bullet integrated it), and the change the
// particle systems make to it.
struct XpbdWorld::Shadow {
  const btCollisionObject* obj = nullptr;
  btRigidBody* dynamic = nullptr;  // set if the body is dynamic (receives impulses)
  btTransform end;                 // Bullet's pose at the end of the step
  btTransform start;               // pose at the start of the step
  btTransform end_to_start_frame;  // maps world points at start pose -> same body points at end pose
  Vec3 v = Vec3::Zero(), w = Vec3::Zero();
  xpbd::RigidBody initial;         // xpbd shadow at the start of the step
  Vec3 dv = Vec3::Zero(), dw = Vec3::Zero(), dx = Vec3::Zero();
  Quat dq = Quat::Identity();
};

struct XpbdWorld::System {
  int id = 0;
  std::shared_ptr<const xpbd::Model> model;
  xpbd::State state;
  SystemSettings settings;
  std::vector<int> shadow_of_body;  // per State::bodies entry: index into shadows_
  std::vector<xpbd::RigidBody> free_bodies;  // scratch: bodies moved without contacts
  ContactScratch contact;                    // scratch of the contact search
};

struct XpbdWorld::Attachment {
  int id = 0;
  int system = 0;
  Index particle = 0;
  btRigidBody* body = nullptr;
  btVector3 local;
  Real compliance = 0;
};

XpbdWorld::XpbdWorld(btDiscreteDynamicsWorld& world) : world_(world) { world_.addAction(this); }

XpbdWorld::~XpbdWorld() { world_.removeAction(this); }

int XpbdWorld::add_system(std::shared_ptr<const xpbd::Model> model, xpbd::State state,
                          const SystemSettings& settings) {
  if (!model) throw xpbd::ConfigError("add_system: model is null");
  check_settings(settings);
  const auto n = static_cast<std::size_t>(model->num_particles());
  if (state.x.size() != n || state.v.size() != n || state.x_prev.size() != n)
    throw xpbd::ConfigError("add_system: state has " + std::to_string(state.x.size()) +
                            " particles, model has " + std::to_string(n) + " (use xpbd::make_state)");
  auto s = std::make_unique<System>();
  s->id = next_id_++;
  s->model = std::move(model);
  s->state = std::move(state);
  s->settings = settings;
  systems_.push_back(std::move(s));
  return systems_.back()->id;
}

void XpbdWorld::remove_system(int id) {
  auto it = std::find_if(systems_.begin(), systems_.end(), [&](auto& s) { return s->id == id; });
  if (it == systems_.end()) throw std::out_of_range("remove_system: no system with id " + std::to_string(id));
  systems_.erase(it);
  std::erase_if(attachments_, [&](const Attachment& a) { return a.system == id; });
}

bool XpbdWorld::has_system(int id) const {
  return std::any_of(systems_.begin(), systems_.end(), [&](auto& s) { return s->id == id; });
}

XpbdWorld::System& XpbdWorld::system(int id) {
  for (auto& s : systems_)
    if (s->id == id) return *s;
  throw std::out_of_range("XpbdWorld: no system with id " + std::to_string(id));
}
const XpbdWorld::System& XpbdWorld::system(int id) const {
  return const_cast<XpbdWorld*>(this)->system(id);
}

xpbd::State& XpbdWorld::state(int id) { return system(id).state; }
const xpbd::State& XpbdWorld::state(int id) const { return system(id).state; }
const xpbd::Model& XpbdWorld::model(int id) const { return *system(id).model; }
SystemSettings& XpbdWorld::settings(int id) { return system(id).settings; }

int XpbdWorld::attach(int id, Index particle, btRigidBody* body, const btVector3& local,
                      Real compliance) {
  System& s = system(id);
  if (particle < 0 || particle >= s.model->num_particles())
    throw xpbd::ConfigError("attach: particle index " + std::to_string(particle) +
                            " out of range [0, " + std::to_string(s.model->num_particles()) + ")");
  if (!body) throw xpbd::ConfigError("attach: body is null");
  if (!in_world(world_, body)) throw xpbd::ConfigError("attach: body is not in the world");
  if (!(compliance >= Real(0)) || !std::isfinite(compliance))
    throw xpbd::ConfigError("attach: compliance must be finite and >= 0, got " + std::to_string(compliance));
  attachments_.push_back(Attachment{next_attachment_, id, particle, body, local, compliance});
  return next_attachment_++;
}

void XpbdWorld::remove_attachment(int attachment_id) {
  const auto n = std::erase_if(attachments_, [&](const Attachment& a) { return a.id == attachment_id; });
  if (n == 0) throw std::out_of_range("remove_attachment: no attachment with id " + std::to_string(attachment_id));
}

// ---------------------------------------------------------------------------

void XpbdWorld::updateAction(btCollisionWorld*, btScalar dt) {
  stats_ = {};
  shadows_.clear();
  for (auto& s : systems_) step_system(*s, dt);
  // Coupling: hand the velocity and position changes to the dynamic bodies.
  // Timed only if a system asks for it (SystemTimes, "coupling").
  const bool timing = !shadows_.empty() && std::any_of(systems_.begin(), systems_.end(), [](const auto& s) {
                        return s->settings.times != nullptr;
                      });
  const auto t0 = timing ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
  for (Shadow& sh : shadows_) {
    btRigidBody* rb = sh.dynamic;
    if (!rb) continue;
    const Real m = Real(1) / rb->getInvMass();
    rb->applyCentralImpulse(to_bt(m * sh.dv));
    // Angular impulse I_world dw, with I = R diag(1/invI) R^T (0 where invI = 0).
    const Quat q = to_quat(sh.end.getRotation());
    const Vec3 inv_i = to_vec(rb->getInvInertiaDiagLocal());
    Vec3 local = q.conjugate() * sh.dw;
    for (int k = 0; k < 3; ++k) local[k] = inv_i[k] > Real(0) ? local[k] / inv_i[k] : Real(0);
    rb->applyTorqueImpulse(to_bt(q * local));
    btTransform t = rb->getCenterOfMassTransform();
    t.setOrigin(t.getOrigin() + to_bt(sh.dx));
    t.setRotation(to_bt(sh.dq * to_quat(t.getRotation())).normalized());
    rb->setCenterOfMassTransform(t);
    rb->activate(true);
  }
  if (timing) {
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count();
    for (auto& s : systems_)
      if (s->settings.times && !s->shadow_of_body.empty()) s->settings.times->ns[SystemTimes::coupling] += ns;
  }
}

int XpbdWorld::shadow_for(const btCollisionObject* obj, btScalar dt) {
  for (std::size_t i = 0; i < shadows_.size(); ++i)
    if (shadows_[i].obj == obj) return static_cast<int>(i);
  Shadow sh;
  sh.obj = obj;
  sh.end = obj->getWorldTransform();
  const btRigidBody* rb = btRigidBody::upcast(obj);
  xpbd::RigidBody& b = sh.initial;
  if (rb) {
    sh.v = to_vec(rb->getLinearVelocity());
    sh.w = to_vec(rb->getAngularVelocity());
    if (!rb->isStaticOrKinematicObject()) {
      sh.dynamic = const_cast<btRigidBody*>(rb);
      b.inv_mass = rb->getInvMass();
      b.inv_inertia = to_vec(rb->getInvInertiaDiagLocal());
    }
  }
  // Bullet's integrator moved the body by x1 = x0 + dt v1 (and the matching
  // rotation), so the start pose is one step back along the end velocity.
  btTransformUtil::integrateTransform(sh.end, to_bt(-sh.v), to_bt(-sh.w), dt, sh.start);
  sh.end_to_start_frame = sh.end * sh.start.inverse();
  b.x = to_vec(sh.start.getOrigin());
  b.q = to_quat(sh.start.getRotation());
  b.v = sh.v;
  b.w = sh.w;
  shadows_.push_back(sh);
  ++stats_.shadows;
  return static_cast<int>(shadows_.size() - 1);
}

Index XpbdWorld::body_index(System& s, const btCollisionObject* obj, btScalar dt) {
  const int sh = shadow_for(obj, dt);
  for (std::size_t i = 0; i < s.shadow_of_body.size(); ++i)
    if (s.shadow_of_body[i] == sh) return static_cast<Index>(i);
  s.shadow_of_body.push_back(sh);
  s.state.bodies.push_back(shadows_[sh].initial);
  return static_cast<Index>(s.state.bodies.size() - 1);
}

void XpbdWorld::find_triangle_contacts(System& s, btScalar dt, const Vec3& lo, const Vec3& hi) {
  const xpbd::Model& m = *s.model;
  xpbd::State& st = s.state;
  const ContactSettings& cs = s.settings.contacts;
  const auto& tris = m.collision_triangles;
  bool bounds_ready = false;
  for (const btCollisionObject* obj : candidates_) {
    features_.clear();
    collect_features(*obj->getCollisionShape(), btTransform::getIdentity(), cs.feature_spacing,
                     features_);
    if (features_.empty()) continue;
    const int shi = shadow_for(obj, dt);
    const btTransform start = shadows_[shi].start;
    const Vec3 vb = shadows_[shi].v;
    const Real wb = shadows_[shi].w.norm();
    if (!bounds_ready) {
      // Each triangle's bounds over the step, grown by the thickness and margin.
      tri_lo_.resize(tris.size());
      tri_hi_.resize(tris.size());
      for (std::size_t t = 0; t < tris.size(); ++t) {
        Vec3 a = Vec3::Constant(std::numeric_limits<Real>::max()), b = -a;
        Real r = 0;
        for (Index p : tris[t]) {
          const Vec3 e = st.x[p] + dt * st.v[p];
          a = a.cwiseMin(st.x[p]).cwiseMin(e);
          b = b.cwiseMax(st.x[p]).cwiseMax(e);
          r = std::max(r, m.radius[p]);
        }
        const Real grow = r + cs.thickness + cs.margin;
        tri_lo_[t] = a.array() - grow;
        tri_hi_[t] = b.array() + grow;
      }
      bounds_ready = true;
    }
    Index body = -1;
    for (const Vec3& local : features_) {
      // The feature at the start of the step and where it moves over the step.
      const Vec3 q0 = to_vec(start * to_bt(local));
      const Real travel = dt * (vb.norm() + wb * local.norm());
      if ((q0.array() + travel < lo.array()).any() || (q0.array() - travel > hi.array()).any())
        continue;
      for (std::size_t t = 0; t < tris.size(); ++t) {
        if ((q0.array() + travel < tri_lo_[t].array()).any() ||
            (q0.array() - travel > tri_hi_[t].array()).any())
          continue;
        const auto& tri = tris[t];
        const Vec3 x1 = st.x[tri[0]], e1 = st.x[tri[1]] - x1, e2 = st.x[tri[2]] - x1;
        const Vec3 nn = e1.cross(e2);
        const Real a2 = nn.squaredNorm();
        if (!(a2 > Real(0))) continue;
        // Barycentric coordinates of the feature's projection: it must lie
        // over the triangle (with a margin of one feature spacing relative to
        // the triangle size, so a corner over a shared edge hits both sides).
        const Vec3 d = q0 - x1;
        const Real u = d.cross(e2).dot(nn) / a2;  // weight of x2
        const Real v = e1.cross(d).dot(nn) / a2;  // weight of x3
        const Real tol = Real(0.05);
        if (u < -tol || v < -tol || u + v > Real(1) + tol) continue;
        const Real dist = d.dot(nn) / std::sqrt(a2);
        Real r = 0;
        for (Index p : tri) r = std::max(r, m.radius[p]);
        const Real thick = r + cs.thickness;
        Real move = travel;
        for (Index p : tri) move = std::max(move, dt * (st.v[p] - vb).norm());
        if (std::abs(dist) > thick + cs.margin + move) continue;
        if (body < 0) body = body_index(s, obj, dt);
        xpbd::BodyTriangleContact c;
        c.body = body;
        c.r = local;
        c.tri = tri;
        c.side = dist >= Real(0) ? Real(1) : Real(-1);
        c.thickness = thick;
        st.triangle_contacts.push_back(c);
      }
    }
  }
  stats_.triangle_contacts += static_cast<int>(st.triangle_contacts.size());
}

void XpbdWorld::step_system(System& s, btScalar dt) {
  const xpbd::Model& m = *s.model;
  xpbd::State& st = s.state;
  const SystemSettings& set = s.settings;
  const ContactSettings& cs = set.contacts;
  const Index n = m.num_particles();

  st.bodies.clear();
  st.contacts.clear();
  st.attachments.clear();
  st.triangle_contacts.clear();
  s.shadow_of_body.clear();
  SystemTimes* const times = set.times;  // opt-in timing (nullptr: none)

  // Attachments whose body is still in the world.
  xpbd::timed(times, SystemTimes::shadows, !attachments_.empty(), [&] {
    for (const Attachment& a : attachments_) {
      if (a.system != s.id || !in_world(world_, a.body)) continue;
      const Index b = body_index(s, a.body, dt);
      st.attachments.push_back(xpbd::BodyAttachment{a.particle, b, to_vec(a.local), a.compliance});
    }
  });

  // Contacts: candidates over the AABB of the particles swept over the step.
  if (cs.enabled && n > 0) {
    const auto t0 = std::chrono::steady_clock::now();
    Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::max());
    Vec3 hi = -lo;
    Real rmax = 0;
    for (Index i = 0; i < n; ++i) {
      const Vec3 e = st.x[i] + dt * st.v[i];
      lo = lo.cwiseMin(st.x[i]).cwiseMin(e);
      hi = hi.cwiseMax(st.x[i]).cwiseMax(e);
      rmax = std::max(rmax, m.radius[i]);
    }
    const Real grow = cs.margin + cs.thickness + rmax;
    lo.array() -= grow;
    hi.array() += grow;
    candidates(world_, lo, hi, candidates_, cs.filter_group, cs.filter_mask);
    stats_.candidates += static_cast<int>(candidates_.size());

    // What the contact loop needs of each candidate (copied: shadow_for()
    // may grow shadows_), and its culling box: the AABB at the start pose
    // grown by grow_b (see "Culling of (particle, body) pairs" above). The
    // shadows are created in candidate order.
    ContactScratch& sc = s.contact;
    const Real system_scale = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
    sc.candidates.clear();
    for (const btCollisionObject* obj : candidates_) {
      const int shi = shadow_for(obj, dt);
      const Shadow& sh = shadows_[shi];
      Candidate c;
      c.obj = obj;
      c.to_end = sh.end_to_start_frame;
      c.end_inv = sh.end.inverse();
      c.vb = sh.v;
      c.wb = sh.w.norm();
      btVector3 amin, amax;
      obj->getCollisionShape()->getAabb(sh.end, amin, amax);
      c.extent = (to_vec(amax) - to_vec(amin)).norm();
      obj->getCollisionShape()->getAabb(sh.start, amin, amax);
      c.box = {to_vec(amin), to_vec(amax)};
      const Real coords =
          std::max({c.box.lo.cwiseAbs().maxCoeff(), c.box.hi.cwiseAbs().maxCoeff(), system_scale});
      const Real grow = dt * (c.vb.norm() + c.wb * c.extent) +
                        Real(4) * xpbd::kDegenerateRel * (Real(1) + coords + c.extent);
      c.box.lo.array() -= grow;
      c.box.hi.array() += grow;
      sc.candidates.push_back(c);
    }
    if (cs.cull) {
      sc.half.resize(std::size_t(n));
      for (Index i = 0; i < n; ++i)
        sc.half[std::size_t(i)] = m.radius[i] + cs.thickness + cs.margin + dt * st.v[i].norm();
      find_pairs(st.x, m.inv_mass, sc);
    }

    for (std::size_t k = 0; k < sc.candidates.size(); ++k) {
      // Local copies: the loop below writes to st.contacts and shadows_.
      const Candidate& cand = sc.candidates[k];
      const btCollisionObject* obj = cand.obj;
      const btTransform to_end = cand.to_end;
      const btTransform end_inv = cand.end_inv;
      const Vec3 vb = cand.vb;
      const Real wb = cand.wb, extent = cand.extent;
      const Real mu_s = cs.static_friction * obj->getFriction();
      const Real mu_d = cs.dynamic_friction * obj->getFriction();
      const Real e = cs.restitution * obj->getRestitution();
      Index body = -1;
      // A particle attached to this body does not collide with it: the
      // attachment holds it at a point of the body, often on its surface,
      // where a contact would push it off by the thickness and fight the
      // attachment at every substep.
      const bool has_attached = std::any_of(attachments_.begin(), attachments_.end(), [&](const Attachment& a) {
        return a.system == s.id && a.body == obj;
      });
      auto attached_here = [&](Index i) {
        return std::any_of(attachments_.begin(), attachments_.end(), [&](const Attachment& a) {
          return a.system == s.id && a.body == obj && a.particle == i;
        });
      };
      // The culled pairs of this candidate, or every particle.
      const Index* const listed = sc.particles.data() + (cs.cull ? sc.pair_begin[k] : 0);
      const Index count = cs.cull ? sc.pair_begin[k + 1] - sc.pair_begin[k] : n;
      for (Index j = 0; j < count; ++j) {
        const Index i = cs.cull ? listed[j] : j;
        if (m.inv_mass[i] == Real(0)) continue;  // never in a culled list
        if (has_attached && attached_here(i)) continue;
        ++stats_.queries;
        const Real thick = m.radius[i] + cs.thickness;
        // The particle's position relative to the body at the start of the
        // step, expressed at the body's end pose (where Bullet's shape is).
        const Vec3 x = to_vec(to_end * to_bt(st.x[i]));
        const Real travel = dt * ((st.v[i] - vb).norm() + wb * extent);
        const Real reach = thick + cs.margin + travel;
        ParticleContact c;
        bool hit = false;
        if (travel > cs.margin) {
          // Fast relative motion: the first surface crossed on the way wins.
          Real frac;
          const Vec3 end = x + dt * (st.v[i] - vb);
          hit = sweep_point(*obj, x, end, c, frac);
        }
        if (!hit) hit = query_point(*obj, x, reach, c);
        if (!hit) continue;
        if (body < 0) body = body_index(s, obj, dt);
        xpbd::BodyContact bc;
        bc.particle = i;
        bc.body = body;
        bc.r = to_vec(end_inv * to_bt(c.point));
        bc.n = to_vec(end_inv.getBasis() * to_bt(c.normal));
        bc.thickness = thick;
        bc.static_friction = mu_s;
        bc.dynamic_friction = mu_d;
        bc.restitution = e;
        bc.compliance = cs.compliance;
        st.contacts.push_back(bc);
      }
    }
    stats_.contacts += static_cast<int>(st.contacts.size());
    if (!m.collision_triangles.empty()) find_triangle_contacts(s, dt, lo, hi);
    const auto t1 = std::chrono::steady_clock::now();
    stats_.contact_seconds += std::chrono::duration<double>(t1 - t0).count();
    if (times) {
      times->ns[SystemTimes::contacts] += std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count();
      ++times->calls[SystemTimes::contacts];
    }
  }

  xpbd::StepConfig cfg;
  cfg.dt = dt;
  cfg.substeps = set.substeps;
  cfg.iterations = set.iterations;
  cfg.method = set.method;
  cfg.drag = set.drag;
  cfg.alternate_sweeps = set.alternate_sweeps;
  cfg.coloured = set.coloured;
  cfg.gravity = to_vec(world_.getGravity());
  cfg.times = times ? &times->step : nullptr;
  // Bodies moved without any contact: the reference the changes are taken from.
  xpbd::timed(times, SystemTimes::shadows, !st.bodies.empty(), [&] {
    s.free_bodies = st.bodies;
    const Real h = dt / Real(set.substeps);
    for (int k = 0; k < set.substeps; ++k) {
      xpbd::rigid::predict_bodies(s.free_bodies, h);
      xpbd::rigid::update_body_velocities(s.free_bodies, h);
    }
  });

  xpbd::step(m, st, cfg);

  // This system's share of the body velocity and position changes.
  xpbd::timed(times, SystemTimes::coupling, !st.bodies.empty(), [&] {
    for (std::size_t i = 0; i < st.bodies.size(); ++i) {
      Shadow& sh = shadows_[s.shadow_of_body[i]];
      if (!sh.dynamic) continue;
      const xpbd::RigidBody& b = st.bodies[i];
      const xpbd::RigidBody& f = s.free_bodies[i];
      sh.dv += b.v - f.v;
      sh.dw += b.w - f.w;
      sh.dx += b.x - f.x;
      sh.dq = (b.q * f.q.conjugate()) * sh.dq;
    }
  });
}

}  // namespace xpbd_bullet
