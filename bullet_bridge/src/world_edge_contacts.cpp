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
#include <limits>
#include <vector>

#include "triangle_bvh.hpp"
#include "world_impl.hpp"

namespace xpbd_bullet {

namespace {

// At most this many contacts per box edge and step (the first found): a
// box edge across a cloth meets a few of its edges per cloth row; many more
// come from a thickness far beyond the cloth's edges.
constexpr int kEdgeContacts = 64;
// Edges closer to parallel than this (sine) are left to the feature points
// along the box edge, as in the solve (rigid_edges.cpp).
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
  const auto& box = static_cast<const btBoxShape&>(shape);
  for (int i = 0; i < box.getNumEdges(); ++i) {
    btVector3 a, b;
    box.getEdge(i, a, b);
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
                     std::vector<std::array<int, 3>>& tri_edges) {
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
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (i == 0 || keys[i].lo != keys[i - 1].lo || keys[i].hi != keys[i - 1].hi) edges.push_back({keys[i].lo, keys[i].hi});
    tri_edges[std::size_t(keys[i].tri)][std::size_t(keys[i].side)] = int(edges.size()) - 1;
  }
}

}  // namespace detail

void XpbdWorld::edge_contacts_of(const System& s, std::size_t k, btScalar dt, const Vec3& sys_lo, const Vec3& sys_hi,
                                 FeatureScratch& fs, CandidateContacts& out) const {
  const xpbd::Model& m = *s.model;
  const xpbd::State& st = s.state;
  const ContactSettings& cs = s.settings.contacts;
  const auto& tris = m.collision_triangles;
  if (s.tri_edges.size() != tris.size() || tri_lo_.size() != tris.size()) return;  // no bounds this step
  const detail::Candidate& cand = s.contact.candidates[k];
  fs.box_edges.clear();
  collect_box_edges(*cand.obj->getCollisionShape(), btTransform::getIdentity(), fs.box_edges);
  if (fs.box_edges.empty()) return;
  const Shadow& sh = shadows_[std::size_t(cand.shadow)];
  const btTransform start = sh.start;
  const Vec3 vb = sh.v;
  const Real ab = dt * sh.accel.norm();
  const Real wb = sh.w.norm() + dt * sh.ang_accel.norm();
  const bool use_bvh = tris.size() >= std::size_t(cs.triangle_bvh_from) && s.tri_bvh;
  if (fs.edge_stamp.size() != s.soft_edges.size()) {
    fs.edge_stamp.assign(s.soft_edges.size(), 0);
    fs.stamp = 0;
  }
  if (use_bvh) {
    fs.body_edges_tris = fs.body_tris;
    std::sort(fs.body_edges_tris.begin(), fs.body_edges_tris.end());
  } else if (fs.all_tris.size() != tris.size()) {
    fs.all_tris.resize(tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) fs.all_tris[t] = int(t);
  }
  for (const auto& [a, b, outward] : fs.box_edges) {
    if (++fs.stamp == 0) {  // wrapped: forget every mark
      std::fill(fs.edge_stamp.begin(), fs.edge_stamp.end(), 0u);
      fs.stamp = 1;
    }
    const Vec3 A = to_vec(start * to_bt(a)), B = to_vec(start * to_bt(b));
    const Vec3 er = B - A;
    const Vec3 out_dir = to_vec(start.getBasis() * to_bt(outward));
    const Real travel = dt * (vb.norm() + ab + wb * std::max(a.norm(), b.norm()));
    // The box edge's box over the step; the triangles' boxes are grown by
    // their thickness and margin already (triangle_bounds).
    const Vec3 lo = (A.cwiseMin(B).array() - travel).matrix(), hi = (A.cwiseMax(B).array() + travel).matrix();
    if ((lo.array() > sys_hi.array()).any() || (hi.array() < sys_lo.array()).any()) continue;  // away from the system
    // With the hierarchy, the triangles near the body's feature points
    // (triangle_contacts_of's query, sorted here once: the box's corners
    // are feature points, so they hold every triangle near its edges);
    // else all of them. In ascending order either way: the same contacts.
    const auto near = [&]() -> const std::vector<int>& {
      if (use_bvh) return fs.body_edges_tris;
      return fs.all_tris;
    }();
    int found = 0;
    for (const int t : near) {
      if ((lo.array() > tri_hi_[std::size_t(t)].array()).any() || (hi.array() < tri_lo_[std::size_t(t)].array()).any())
        continue;
      for (const int e : s.tri_edges[std::size_t(t)]) {
        if (fs.edge_stamp[std::size_t(e)] == fs.stamp || found == kEdgeContacts) continue;
        fs.edge_stamp[std::size_t(e)] = fs.stamp;
        const auto [p0, p1] = s.soft_edges[std::size_t(e)];
        const Vec3 P = st.x[p0], es = st.x[p1] - P;
        const Vec3 nn = er.cross(es);
        const Real rr = er.squaredNorm(), ss = es.squaredNorm(), n2 = nn.squaredNorm();
        if (!(n2 > kParallelSin * kParallelSin * rr * ss)) continue;
        const Vec3 w0 = A - P;
        const Real rs = er.dot(es), d = er.dot(w0), f = es.dot(w0);
        const Real u = (rs * f - ss * d) / n2, v = (rr * f - rs * d) / n2;
        if (!(u >= Real(0) && u <= Real(1) && v >= Real(0) && v <= Real(1))) continue;
        // The side is the outside of the box edge, whichever side the soft
        // edge starts on: one that has just gone through is pushed back
        // out, not held inside.
        const Real lean = nn.dot(out_dir) / std::sqrt(n2);
        if (!(std::abs(lean) >= xpbd::kEdgeLean)) continue;
        const Real dist = nn.dot(P - A) / std::sqrt(n2);
        const Real thick = std::max({m.radius[p0], m.radius[p1], Real(0)}) + cs.thickness;
        const Real move = std::max(travel, dt * (std::max((st.v[p0] - vb).norm(), (st.v[p1] - vb).norm()) + ab));
        // Nearer than the band on the outside, or inside by at most the
        // thickness. Deeper inside, the soft edge has gone through at
        // speed (a blade's edge), and it is neither held there nor pushed
        // out over the edge from deep in (the particle contacts answer).
        const Real out_dist = lean > Real(0) ? dist : -dist;
        if (!(out_dist <= thick + cs.margin + move) || !(out_dist >= -thick)) continue;
        if (++found == kEdgeContacts) ++out.capped;
        xpbd::BodyEdgeContact c;  // body: set when joined (step_system)
        c.a = a;
        c.b = b;
        c.p = {p0, p1};
        c.out = outward;
        c.thickness = thick;
        c.reach = cs.margin;
        c.closing_speed = move / dt;
        out.edge.push_back(c);
      }
    }
  }
}

}  // namespace xpbd_bullet
