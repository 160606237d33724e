// XpbdWorld's contacts between the edges of box shapes and the edges of a
// system's collision triangles (ContactSettings::edge_contacts,
// xpbd::BodyEdgeContact): the soft edges near each box edge from the
// triangles' hierarchy (or all of them), the two lines' closest points at
// the start of the step, and a contact for a pair closer than the
// thickness, margin and travel. One candidate body per call of
// edge_contacts_of, which only reads the world and the system (step_system
// may run it on several threads).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "triangle_bvh.hpp"
#include "world_impl.hpp"

namespace xpbd_bullet {

namespace {

// At most this many contacts per box edge and step (the first found), or
// kEdgePerPiece per feature_spacing of its length if that is more: a box
// edge across a cloth meets two or three of its edges per cloth row, and
// feature_spacing is below the cloth's edge length; many more come from a
// thickness far beyond the cloth's edges. The edge contacts are all that
// holds a cloth along a box edge (its feature points are its two corners),
// so a long edge under a fine cloth must not run out of them.
constexpr int kEdgeContacts = 64;
constexpr int kEdgePerPiece = 4;
// Edges closer to parallel than this (sine) are left to the soft edge's
// particle contacts, as in the solve (rigid_edges.cpp).
constexpr Real kParallelSin = Real(0.02);

// The soft edge's side of a box edge is its outside: the normal of the
// contact must lean at least xpbd::kEdgeLean (cosine) towards the box
// edge's outward bisector, or the pair has no outside along it (a soft
// edge lying along the corner) and gets no contact (the solve takes the
// same test at every evaluation).

// The edges of the box shapes in `shape` (compounds followed), body frame:
// the ends and the outward bisector of the two faces that meet there.
void collect_box_edges(const btCollisionShape& shape, const btTransform& t, std::vector<std::array<Vec3, 3>>& out) {
  if (shape.isCompound()) {
    const auto& c = static_cast<const btCompoundShape&>(shape);
    for (int i = 0; i < c.getNumChildShapes(); ++i)
      collect_box_edges(*c.getChildShape(i), t * c.getChildTransform(i), out);
    return;
  }
  if (shape.getShapeType() != BOX_SHAPE_PROXYTYPE) return;
  // btBoxShape::getEdge's twelve edges in its order, as pairs of its
  // vertices; vertex i (getVertex) is the half extents (with the margin)
  // with axis k negated where bit k of i is set. Taken here from one call
  // for the half extents, not 24 virtual calls per box and step.
  static constexpr std::array<std::array<int, 2>, 12> kEdges{
      {{0, 1}, {0, 2}, {1, 3}, {2, 3}, {0, 4}, {1, 5}, {2, 6}, {3, 7}, {4, 5}, {4, 6}, {5, 7}, {6, 7}}};
  const btVector3 h = static_cast<const btBoxShape&>(shape).getHalfExtentsWithMargin();
  const auto vertex = [&h](int i) {
    return btVector3((i & 1) ? -h.x() : h.x(), (i & 2) ? -h.y() : h.y(), (i & 4) ? -h.z() : h.z());
  };
  for (const auto& [i0, i1] : kEdges) {
    const btVector3 a = vertex(i0), b = vertex(i1);
    // The bisector of the two faces' outward normals: the edge runs along
    // one axis, and its midpoint is at +-half extent on the other two (the
    // box is centred on its own origin). Not the midpoint's direction off
    // the axis: on a thin box (a 1 cm blade 0.4 m long) that is nearly the
    // larger face's normal.
    const btVector3 mid = (a + b) * btScalar(0.5), axis = (b - a).normalized();
    btVector3 out_dir(0, 0, 0);
    for (int k = 0; k < 3; ++k)
      if (std::abs(axis[k]) < btScalar(0.5)) out_dir[k] = mid[k] > btScalar(0) ? btScalar(1) : btScalar(-1);
    out.push_back({to_vec(t * a), to_vec(t * b), to_vec(t.getBasis() * out_dir).normalized()});
  }
}

}  // namespace

namespace detail {

// Declared in world_impl.hpp.
void find_soft_edges(const std::vector<std::array<xpbd::Index, 3>>& tris, std::vector<std::array<xpbd::Index, 2>>& edges,
                     std::vector<std::array<int, 3>>& tri_edges, std::vector<std::uint8_t>& tri_owns) {
  // Each edge as (lower, upper, triangle, side), sorted: equal edges meet.
  struct Key {
    xpbd::Index lo, hi;
    int tri, side;
  };
  std::vector<Key> keys;
  keys.reserve(3 * tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int i = 0; i < 3; ++i) {
      const xpbd::Index a = tris[t][std::size_t(i)], b = tris[t][std::size_t((i + 1) % 3)];
      keys.push_back({std::min(a, b), std::max(a, b), int(t), i});
    }
  std::sort(keys.begin(), keys.end(), [](const Key& x, const Key& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.tri != y.tri ? x.tri < y.tri : x.side < y.side;
  });
  edges.clear();
  tri_edges.assign(tris.size(), {0, 0, 0});
  tri_owns.assign(tris.size(), 0);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (i == 0 || keys[i].lo != keys[i - 1].lo || keys[i].hi != keys[i - 1].hi) {
      edges.push_back({keys[i].lo, keys[i].hi});
      tri_owns[std::size_t(keys[i].tri)] |= std::uint8_t(1u << keys[i].side);  // its first triangle and side
    }
    tri_edges[std::size_t(keys[i].tri)][std::size_t(keys[i].side)] = int(edges.size()) - 1;
  }
}

void surface_edges(const xpbd::Model& m, std::vector<std::array<xpbd::Index, 2>>& edges,
                   std::vector<std::array<int, 3>>& tri_edges, std::vector<std::uint8_t>& tri_owns,
                   std::vector<int>& edge_begin, std::vector<int>& edges_at) {
  find_soft_edges(m.surface_triangles, edges, tri_edges, tri_owns);
  const std::size_t n = std::size_t(m.num_particles());
  edge_begin.assign(n + 1, 0);
  for (const auto& [a, b] : edges) {
    ++edge_begin[std::size_t(a) + 1];
    ++edge_begin[std::size_t(b) + 1];
  }
  for (std::size_t i = 0; i < n; ++i) edge_begin[i + 1] += edge_begin[i];
  edges_at.assign(std::size_t(edge_begin[n]), 0);
  std::vector<int> fill(edge_begin.begin(), edge_begin.end() - 1);
  for (std::size_t e = 0; e < edges.size(); ++e)
    for (const xpbd::Index p : edges[e]) edges_at[std::size_t(fill[std::size_t(p)]++)] = int(e);
}

bool has_box_edges(const btCollisionShape& shape) {
  if (shape.isCompound()) {
    const auto& c = static_cast<const btCompoundShape&>(shape);
    for (int i = 0; i < c.getNumChildShapes(); ++i)
      if (has_box_edges(*c.getChildShape(i))) return true;
    return false;
  }
  return shape.getShapeType() == BOX_SHAPE_PROXYTYPE;
}

Box soft_edge_box(const xpbd::Model& m, const xpbd::State& st, xpbd::Index p0, xpbd::Index p1, Real dt,
                  Real thickness, Real margin) {
  const Real grow = std::max({m.radius[p0], m.radius[p1], Real(0)}) + thickness + margin;
  const Vec3 e0 = st.x[p0] + dt * st.v[p0], e1 = st.x[p1] + dt * st.v[p1];
  return {(st.x[p0].cwiseMin(e0).cwiseMin(st.x[p1]).cwiseMin(e1).array() - grow).matrix(),
          (st.x[p0].cwiseMax(e0).cwiseMax(st.x[p1]).cwiseMax(e1).array() + grow).matrix()};
}

void widen_for_edges(const xpbd::Model& m, const xpbd::State& st, Real dt,
                     const std::vector<std::array<xpbd::Index, 2>>& edges, std::vector<Real>& reach,
                     std::vector<Real>& half) {
  reach.assign(half.size(), Real(0));
  // How far the far end (and its path, and its larger radius) reaches from x_i.
  const auto far = [&](xpbd::Index i, xpbd::Index j) {
    return (st.x[j] - st.x[i]).norm() + dt * st.v[j].norm() + std::max(m.radius[j] - m.radius[i], Real(0));
  };
  for (const auto& [a, b] : edges) {
    // A NaN stays (the culling tests such a particle against every box).
    const Real ra = far(a, b), rb = far(b, a);
    Real& xa = reach[std::size_t(a)];
    Real& xb = reach[std::size_t(b)];
    if (!(xa >= ra)) xa = ra;
    if (!(xb >= rb)) xb = rb;
  }
  // Round-off: the candidate boxes hold a slack of 4 kDegenerateRel
  // relative to the coordinates (world_contacts.cpp); this adds one more
  // relative to the reach.
  for (std::size_t i = 0; i < half.size(); ++i) half[i] += reach[i] * (Real(1) + xpbd::kDegenerateRel);
}

}  // namespace detail

void XpbdWorld::edge_contacts_of(const System& s, std::size_t k, btScalar dt, const Vec3& sys_lo, const Vec3& sys_hi,
                                 FeatureScratch& fs, CandidateContacts& out) const {
  const xpbd::Model& m = *s.model;
  const xpbd::State& st = s.state;
  const ContactSettings& cs = s.settings.contacts;
  const auto& tris = m.collision_triangles;
  // Without collision triangles: the surface triangles' edges at the
  // particles the culling found near the body (every particle without the
  // culling); those at or next to a particle attached to it with no
  // thickness (below).
  const bool surface = tris.empty();
  if (surface ? s.tri_edges.size() != m.surface_triangles.size()
              : (s.tri_edges.size() != tris.size() || tri_lo_.size() != tris.size()))
    return;  // no edges, or no bounds this step
  const detail::Candidate& cand = s.contact.candidates[k];
  fs.box_edges.clear();
  collect_box_edges(*cand.obj->getCollisionShape(), btTransform::getIdentity(), fs.box_edges);
  if (fs.box_edges.empty()) return;
  const Shadow& sh = shadows_[std::size_t(cand.shadow)];
  const btTransform start = sh.start;
  const Vec3 vb = sh.v;
  const Real ab = dt * sh.accel.norm();
  const Real wb = sh.w.norm() + dt * sh.ang_accel.norm();
  const bool use_bvh = !surface && tris.size() >= std::size_t(cs.triangle_bvh_from) && s.tri_bvh;

  // Each box edge at the start of the step (world), and its box over the
  // step; rigid: the box edges near the system, and `reach` the union of
  // their boxes.
  struct RigidEdge {
    Vec3 a, b, outward;  // body frame (the contact's)
    Vec3 A, B, out_dir;  // world, at the step's start
    Vec3 lo, hi;         // its box over the step
    Real travel;
  };
  std::array<RigidEdge, 12> rigid_buf;
  std::vector<RigidEdge> rigid_many;
  const std::size_t nr_all = fs.box_edges.size();
  RigidEdge* rigid = nr_all <= rigid_buf.size() ? rigid_buf.data() : (rigid_many.resize(nr_all), rigid_many.data());
  std::size_t nr = 0;
  Vec3 reach_lo = Vec3::Constant(std::numeric_limits<Real>::max()), reach_hi = -reach_lo;
  for (const auto& [a, b, outward] : fs.box_edges) {
    RigidEdge& r = rigid[nr];
    r.a = a;
    r.b = b;
    r.outward = outward;
    r.A = to_vec(start * to_bt(a));
    r.B = to_vec(start * to_bt(b));
    r.out_dir = to_vec(start.getBasis() * to_bt(outward));
    r.travel = dt * (vb.norm() + ab + wb * std::max(a.norm(), b.norm()));
    r.lo = (r.A.cwiseMin(r.B).array() - r.travel).matrix();
    r.hi = (r.A.cwiseMax(r.B).array() + r.travel).matrix();
    if ((r.lo.array() > sys_hi.array()).any() || (r.hi.array() < sys_lo.array()).any()) continue;  // away from the system
    reach_lo = reach_lo.cwiseMin(r.lo);
    reach_hi = reach_hi.cwiseMax(r.hi);
    ++nr;
  }
  if (nr == 0) return;

  // The soft edges that may meet a box edge, each once, in the order they
  // are tested, and whether each is held (below); then their boxes over
  // the step (detail::soft_edge_box), which each box edge's box must meet.
  fs.near_pairs.clear();
  fs.near_held.clear();
  if (surface) {
    fs.near_edges.clear();
    const detail::ContactScratch& sc = s.contact;
    const bool has_attached = std::any_of(attachments_.begin(), attachments_.end(), [&](const Attachment& a) {
      return a.system == s.id && a.body == cand.obj;
    });
    // Held: a particle attached to the body, or one edge from it. The
    // attachment keeps such a particle on the body's face, inside the
    // thickness, and the cloth around it lies along the face (a tarp
    // fastened under a crate): a soft edge there is held out of the body
    // with no thickness, so that it does not pass through the body's edge
    // (a cloth hanging from a bar wrapped around the bar's long edge:
    // docs/squeeze-surface-edges.md) and does not lift the body off the particles either.
    const auto held = [&](Index p) {
      if (attached(s, cand.obj, p)) return true;
      for (int q = s.edge_begin[std::size_t(p)]; q < s.edge_begin[std::size_t(p) + 1]; ++q) {
        const auto [a0, a1] = s.soft_edges[std::size_t(s.edges_at[std::size_t(q)])];
        if (attached(s, cand.obj, a0 == p ? a1 : a0)) return true;
      }
      return false;
    };
    // The edges with a movable end whose box meets the candidate's, in
    // ascending order: from the culled particles' edges (the culling's
    // half sizes hold each particle's edges' boxes,
    // detail::widen_for_edges), or from every edge. The same edges either
    // way.
    const auto take = [&](int e) {
      const auto [p0, p1] = s.soft_edges[std::size_t(e)];
      if (m.inv_mass[p0] == Real(0) && m.inv_mass[p1] == Real(0)) return;
      const detail::Box eb = detail::soft_edge_box(m, st, p0, p1, dt, cs.thickness, cs.margin);
      if ((eb.lo.array() > cand.box.hi.array()).any() || (eb.hi.array() < cand.box.lo.array()).any()) return;
      fs.near_edges.push_back(2 * e + int(has_attached && (held(p0) || held(p1))));
    };
    if (cs.cull) {
      if (fs.edge_stamp.size() != s.soft_edges.size()) {
        fs.edge_stamp.assign(s.soft_edges.size(), 0);
        fs.stamp = 0;
      }
      if (++fs.stamp == 0) {  // wrapped: forget every mark
        std::fill(fs.edge_stamp.begin(), fs.edge_stamp.end(), 0u);
        fs.stamp = 1;
      }
      for (Index j = sc.pair_begin[k]; j < sc.pair_begin[k + 1]; ++j) {
        const Index i = sc.particles[std::size_t(j)];
        for (int q = s.edge_begin[std::size_t(i)]; q < s.edge_begin[std::size_t(i) + 1]; ++q) {
          const int e = s.edges_at[std::size_t(q)];
          if (fs.edge_stamp[std::size_t(e)] == fs.stamp) continue;
          fs.edge_stamp[std::size_t(e)] = fs.stamp;
          take(e);
        }
      }
      std::sort(fs.near_edges.begin(), fs.near_edges.end());
    } else {
      for (std::size_t e = 0; e < s.soft_edges.size(); ++e) take(int(e));
    }
    for (const int coded : fs.near_edges) {
      fs.near_pairs.push_back(s.soft_edges[std::size_t(coded / 2)]);
      fs.near_held.push_back(std::uint8_t(coded & 1));
    }
  } else {
    // The edges of the triangles whose box meets the box edges' boxes,
    // each from the first triangle that has it (System::tri_owns), in
    // ascending order of that triangle, then side: with the hierarchy,
    // among the triangles near the body's feature points
    // (triangle_contacts_of's query; the box's corners are feature points,
    // so they hold every triangle near its edges); else among all of them.
    // A soft edge's box lies in both its triangles' boxes, so every edge
    // whose box meets a box edge's is taken, once, in the same order either
    // way. (Not a mark per edge: the triangles' own corners are at hand,
    // where the edges' list and the marks cost a cache miss each on a
    // large cloth.)
    const auto edges_of = [&](const int t) {
      const unsigned own = s.tri_owns[std::size_t(t)];
      if (own == 0 || (reach_lo.array() > tri_hi_[std::size_t(t)].array()).any() ||
          (reach_hi.array() < tri_lo_[std::size_t(t)].array()).any())
        return;
      const auto& tri = tris[std::size_t(t)];
      for (std::size_t i = 0; i < 3; ++i)
        if ((own >> i) & 1u) {
          const Index a = tri[i], b = tri[(i + 1) % 3];
          fs.near_pairs.push_back({std::min(a, b), std::max(a, b)});
          fs.near_held.push_back(0);
        }
    };
    if (use_bvh)
      for (const int t : fs.body_tris) edges_of(t);
    else
      for (std::size_t t = 0; t < tris.size(); ++t) edges_of(int(t));
  }
  if (fs.near_pairs.empty()) return;
  fs.edge_lo.resize(fs.near_pairs.size());
  fs.edge_hi.resize(fs.near_pairs.size());
  for (std::size_t j = 0; j < fs.near_pairs.size(); ++j) {
    const auto [p0, p1] = fs.near_pairs[j];
    const detail::Box eb = detail::soft_edge_box(m, st, p0, p1, dt, cs.thickness, cs.margin);
    fs.edge_lo[j] = eb.lo;
    fs.edge_hi[j] = eb.hi;
  }
  fs.edge_boxes.assign(fs.edge_lo, fs.edge_hi);

  for (std::size_t ri = 0; ri < nr; ++ri) {
    const RigidEdge& r = rigid[ri];
    const Vec3 &A = r.A, &out_dir = r.out_dir;
    const Vec3 er = r.B - r.A;
    const Real rr = er.squaredNorm();
    int found = 0;
    // Clamped before the cast: a huge edge (or a NaN) must not overflow it.
    const Real pieces = std::ceil((r.b - r.a).norm() / cs.feature_spacing);
    const int cap = pieces > Real(kEdgeContacts / kEdgePerPiece)
                        ? (pieces < Real(1 << 16) ? kEdgePerPiece * static_cast<int>(pieces) : kEdgePerPiece << 16)
                        : kEdgeContacts;
    fs.edge_found.clear();
    fs.edge_boxes.overlapping(r.lo, r.hi, fs.edge_found);
    // The pair (box edge, soft edge e): a contact if the two lines' closest
    // points lie on both edges, near enough, on a side that leans outwards.
    // held: a soft edge at or next to a particle attached to the body,
    // kept out with no thickness (above).
    for (const int j : fs.edge_found) {
      const bool held = fs.near_held[std::size_t(j)] != 0;
      const auto [p0, p1] = fs.near_pairs[std::size_t(j)];
      const Vec3 P = st.x[p0], es = st.x[p1] - P;
      const Vec3 nn = er.cross(es);
      const Real ss = es.squaredNorm(), n2 = nn.squaredNorm();
      // The closest points at u and v along the two edges, times n2.
      const Vec3 w0 = A - P;
      const Real rs = er.dot(es), d = er.dot(w0), f = es.dot(w0);
      const Real u = rs * f - ss * d, v = rr * f - rs * d;
      // The side is the outside of the box edge, whichever side the soft
      // edge starts on: one that has just gone through is pushed back
      // out, not held inside. Its lean (cosine) is nl / |nn|.
      const Real nl = nn.dot(out_dir);
      // Not parallel (the closest points then lie on both edges), and
      // leaning outwards; tested at once, without a branch per test (most
      // pairs end here, on any of them, at random).
      const bool near = (n2 > kParallelSin * kParallelSin * rr * ss) & (u >= Real(0)) & (u <= n2) & (v >= Real(0)) &
                        (v <= n2) & (nl * nl >= xpbd::kEdgeLean * xpbd::kEdgeLean * n2);
      if (!near) continue;
      const Real inv = Real(1) / std::sqrt(n2);
      const Real lean = nl * inv;
      const Real dist = nn.dot(P - A) * inv;
      const Real thick = std::max({m.radius[p0], m.radius[p1], Real(0)}) + cs.thickness;
      const Real move = std::max(r.travel, dt * (std::max((st.v[p0] - vb).norm(), (st.v[p1] - vb).norm()) + ab));
      // Nearer than the band on the outside, or inside by at most the
      // thickness. Deeper inside, the soft edge has gone through at
      // speed (a blade's edge), and it is neither held there nor pushed
      // out over the edge from deep in (the particle contacts answer).
      const Real out_dist = lean > Real(0) ? dist : -dist;
      if (!(out_dist <= thick + cs.margin + move) || !(out_dist >= -thick)) continue;
      if (++found == cap) ++out.capped;
      xpbd::BodyEdgeContact c;  // body: set when joined (step_system)
      c.a = r.a;
      c.b = r.b;
      c.p = {p0, p1};
      c.out = r.outward;
      c.thickness = held ? std::max({m.radius[p0], m.radius[p1], Real(0)}) : thick;
      c.reach = cs.margin;
      c.closing_speed = move / dt;
      c.static_friction = cs.static_friction * cand.obj->getFriction();
      c.dynamic_friction = cs.dynamic_friction * cand.obj->getFriction();
      out.edge.push_back(c);
      if (found == cap) break;
    }
  }
}

}  // namespace xpbd_bullet
