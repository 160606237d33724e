// XpbdWorld's contacts between rigid features (box corners and edge
// points, hull vertices, the sharp edges and corners of static triangle
// meshes) and a system's collision triangles: the
// candidates from FCL's hierarchy of the triangles (triangle_bvh.hpp), the
// exact tests, and the sweep of fast features (feature_sweep.hpp). One
// candidate body per call of triangle_contacts_of, which only reads the
// world and the system (step_system may run it on several threads).
#include <LinearMath/btTransformUtil.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "feature_sweep.hpp"
#include "triangle_grid.hpp"
#include "world_impl.hpp"

namespace xpbd_bullet {

namespace {

// Two faces closer to flat than about a degree meet at no feature.
constexpr Real kFlatCos = Real(0.99985);

// The triangles of a concave shape that overlap a box (its own frame).
struct TriangleGrab : btTriangleCallback {
  std::vector<std::array<Vec3, 3>>* out;
  void processTriangle(btVector3* t, int, int) override {
    out->push_back({to_vec(t[0]), to_vec(t[1]), to_vec(t[2])});
  }
};

// Shapes made of triangles (BVH meshes, scaled or multi-material, and
// heightfields), as narrowphase.cpp answers them (narrowphase_triangles.cpp).
bool is_triangle_mesh(const btCollisionShape& shape) {
  switch (shape.getShapeType()) {
    case TRIANGLE_MESH_SHAPE_PROXYTYPE:
    case SCALED_TRIANGLE_MESH_SHAPE_PROXYTYPE:
    case MULTIMATERIAL_TRIANGLE_MESH_PROXYTYPE:
    case TERRAIN_SHAPE_PROXYTYPE: return true;
    default: return false;
  }
}

bool less_vec(const Vec3& a, const Vec3& b) {
  return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
}

}  // namespace

namespace detail {

// Declared in world_impl.hpp.
void collect_mesh_features(const btConcaveShape& shape, const Vec3& lo, const Vec3& hi, Real spacing,
                           std::vector<std::array<Vec3, 3>>& tris, std::vector<Vec3>& out) {
  tris.clear();
  TriangleGrab grab;
  grab.out = &tris;
  shape.processAllTriangles(&grab, to_bt(lo), to_bt(hi));
  // Every edge of every triangle, as (lower end, upper end) in
  // lexicographic order, with the triangle it came from: sorted, the
  // triangles sharing an edge are neighbours.
  struct Edge {
    Vec3 a, b;
    std::size_t tri;
  };
  std::vector<Edge> edges;
  edges.reserve(3 * tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int i = 0; i < 3; ++i) {
      Vec3 a = tris[t][i], b = tris[t][(i + 1) % 3];
      if (less_vec(b, a)) std::swap(a, b);
      edges.push_back({a, b, t});
    }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    if (x.a != y.a) return less_vec(x.a, y.a);
    if (x.b != y.b) return less_vec(x.b, y.b);
    return x.tri < y.tri;
  });
  const std::size_t first = out.size();
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
    // Sharp: an open edge (one triangle, or more than two), or two
    // triangles more than about a degree from flat, ridge or valley (which
    // is which depends on the winding, which meshes do not agree on; a
    // valley under a cloth costs a few contacts and is right anyway).
    // Flat edges (a face's diagonal) are no features.
    bool sharp = j - i != 2;
    if (j - i == 2) {
      const auto& t1 = tris[edges[i].tri];
      const auto& t2 = tris[edges[i + 1].tri];
      const Vec3 n1 = (t1[1] - t1[0]).cross(t1[2] - t1[0]);
      const Vec3 n2 = (t2[1] - t2[0]).cross(t2[2] - t2[0]);
      const Real nn = std::sqrt(n1.squaredNorm() * n2.squaredNorm());
      sharp = !(nn > Real(0)) || std::abs(n1.dot(n2)) < kFlatCos * nn;
    }
    if (sharp) {
      const Vec3 a = edges[i].a, b = edges[i].b;
      out.push_back(a);
      out.push_back(b);
      const int pieces = static_cast<int>(std::ceil((b - a).norm() / spacing));
      for (int k = 1; k < pieces; ++k) out.push_back(a + (Real(k) / Real(pieces)) * (b - a));
    }
    i = j;
  }
  // Each corner once (edges share them).
  std::sort(out.begin() + std::ptrdiff_t(first), out.end(), less_vec);
  out.erase(std::unique(out.begin() + std::ptrdiff_t(first), out.end()), out.end());
}


// Declared in world_impl.hpp.
void collect_features(const btCollisionShape& shape, const btTransform& t, Real spacing, std::vector<Vec3>& out,
                      bool edges, std::vector<Vec3>* centres) {
  if (shape.isCompound()) {
    const auto& c = static_cast<const btCompoundShape&>(shape);
    for (int i = 0; i < c.getNumChildShapes(); ++i)
      collect_features(*c.getChildShape(i), t * c.getChildTransform(i), spacing, out, edges, centres);
    return;
  }
  if (!shape.isPolyhedral()) return;
  const auto& p = static_cast<const btPolyhedralConvexShape&>(shape);
  const std::size_t first = out.size();
  Vec3 mean = Vec3::Zero();  // of the vertices: inside the convex shape (its origin need not be)
  for (int i = 0; i < p.getNumVertices(); ++i) {
    btVector3 v;
    p.getVertex(i, v);
    out.push_back(to_vec(t * v));
    mean += out.back();
  }
  if (out.size() > first) mean /= Real(out.size() - first);
  if (edges && shape.getShapeType() == BOX_SHAPE_PROXYTYPE) {
    for (int i = 0; i < p.getNumEdges(); ++i) {
      btVector3 a, b;
      p.getEdge(i, a, b);
      const Vec3 pa = to_vec(t * a), pb = to_vec(t * b);
      const int pieces = static_cast<int>(std::ceil((pb - pa).norm() / spacing));
      for (int k = 1; k < pieces; ++k) out.push_back(pa + (Real(k) / Real(pieces)) * (pb - pa));
    }
  }
  if (centres != nullptr) centres->resize(out.size(), mean);
}

}  // namespace detail

// A body's features times the triangles near it, up to which each feature
// tests every one of those triangles, many boxes at a time (box_list.hpp):
// a box's 8 corners and up to 512 triangles. Above it, the triangles go
// into a grid over the features, or, with more than kBodyTriangles of them,
// each feature queries the hierarchy itself (bench_triangles).
constexpr std::size_t kBruteTests = 4096;
constexpr std::size_t kBodyTriangles = 256;
// At most this many pieces of a fast feature's path per step.
constexpr int kSweepPieces = 16;
// At most this many contacts per feature and step (the first found).
constexpr int kFeatureTriangles = 16;
// A body's grid cell (triangle_grid.hpp), in sides of its candidate
// triangles' boxes (their mean largest side).
constexpr Real kCellPerTriangle = Real(0.5);

namespace {

// Whether a point that may move `travel` along each axis stays outside the
// box [lo, hi]; without branches, as most tests end here.
inline bool outside(const Vec3& q, Real travel, const Vec3& lo, const Vec3& hi) {
  return static_cast<bool>(static_cast<int>(q.x() + travel < lo.x()) | static_cast<int>(q.y() + travel < lo.y()) |
                           static_cast<int>(q.z() + travel < lo.z()) | static_cast<int>(q.x() - travel > hi.x()) |
                           static_cast<int>(q.y() - travel > hi.y()) | static_cast<int>(q.z() - travel > hi.z()));
}

}  // namespace

namespace detail {

// Declared in world_impl.hpp.
bool may_have_features(const btCollisionObject& obj) {
  const btCollisionShape& shape = *obj.getCollisionShape();
  const auto polyhedral = [](const btCollisionShape& sh, const auto& self) -> bool {
    if (!sh.isCompound()) return sh.isPolyhedral();
    const auto& c = static_cast<const btCompoundShape&>(sh);
    for (int i = 0; i < c.getNumChildShapes(); ++i)
      if (self(*c.getChildShape(i), self)) return true;
    return false;
  };
  return polyhedral(shape, polyhedral) || (obj.isStaticOrKinematicObject() && is_triangle_mesh(shape));
}

}  // namespace detail

void XpbdWorld::triangle_bounds(System& s, btScalar dt) {
  const xpbd::Model& m = *s.model;
  const xpbd::State& st = s.state;
  const ContactSettings& cs = s.settings.contacts;
  const auto& tris = m.collision_triangles;
  // Each particle's box over the step, then each triangle's bounds over
  // them, grown by the thickness and margin (in pieces on the system's
  // pool, if it has one; min and max are exact, so the boxes are those of
  // the triangles' own particles in any order).
  const std::size_t np = st.x.size();
  sweep_lo_.resize(np);
  sweep_hi_.resize(np);
  detail::for_each_chunk(s.settings.workers, np, 4096, [&](std::size_t begin, std::size_t end, std::size_t) {
    for (std::size_t p = begin; p < end; ++p) {
      const Vec3 e = st.x[p] + dt * st.v[p];
      sweep_lo_[p] = st.x[p].cwiseMin(e);
      sweep_hi_[p] = st.x[p].cwiseMax(e);
    }
  });
  tri_lo_.resize(tris.size());
  tri_hi_.resize(tris.size());
  detail::for_each_chunk(s.settings.workers, tris.size(), 2048, [&](std::size_t begin, std::size_t end, std::size_t) {
    for (std::size_t t = begin; t < end; ++t) {
      const auto [p0, p1, p2] = tris[t];
      const Real r = std::max({m.radius[p0], m.radius[p1], m.radius[p2], Real(0)});
      const Real grow = r + cs.thickness + cs.margin;
      tri_lo_[t] = sweep_lo_[std::size_t(p0)].cwiseMin(sweep_lo_[std::size_t(p1)]).cwiseMin(sweep_lo_[std::size_t(p2)]).array() - grow;
      tri_hi_[t] = sweep_hi_[std::size_t(p0)].cwiseMax(sweep_hi_[std::size_t(p1)]).cwiseMax(sweep_hi_[std::size_t(p2)]).array() + grow;
    }
  });
  if (s.tri_edges.size() != tris.size()) detail::find_soft_edges(tris, s.soft_edges, s.tri_edges, s.tri_owns);
  if (tris.size() >= std::size_t(cs.triangle_bvh_from)) {
    if (!s.tri_bvh) s.tri_bvh = std::make_unique<detail::TriangleBvh>();
    s.tri_bvh->update(tris, st.x, tri_lo_, tri_hi_, s.settings.workers);
  }
}

void XpbdWorld::triangle_contacts_of(const System& s, std::size_t k, btScalar dt, const Vec3& lo, const Vec3& hi,
                                     FeatureScratch& fs, CandidateContacts& out) const {
  const xpbd::Model& m = *s.model;
  const xpbd::State& st = s.state;
  const ContactSettings& cs = s.settings.contacts;
  const auto& tris = m.collision_triangles;
  const bool use_bvh = tris.size() >= std::size_t(cs.triangle_bvh_from);
  const detail::Candidate& cand = s.contact.candidates[k];
  const btCollisionObject* obj = cand.obj;
  std::vector<Vec3>& features = fs.features;
  std::vector<Vec3>& centres = fs.centres;
  std::array<Vec3, kSweepPieces + 1> path_at;  // a fast feature's path
  Vec3 path_lo, path_hi;                       // and its box
  features.clear();
  centres.clear();
  fs.body_tris.clear();  // read by edge_contacts_of after this call
  const btCollisionShape& shape = *obj->getCollisionShape();
  // A box's edges are held by the edge contacts when they are on
  // (edge_contacts_of): its feature points are then its corners alone,
  // unless the body is fast (below).
  detail::collect_features(shape, btTransform::getIdentity(), cs.feature_spacing, features, !cs.edge_contacts,
                           &centres);
  const Shadow& sh = shadows_[std::size_t(cand.shadow)];
  const bool mesh = features.empty() && obj->isStaticOrKinematicObject() && is_triangle_mesh(shape);
  if (mesh) {
    // A static or kinematic triangle mesh: the sharp edges and corners of
    // its triangles within the system's box, in the mesh's frame. A
    // kinematic mesh moves over the step (from its shadow's start to the
    // pose Bullet has put it at): the box is taken in its frame at both
    // ends, grown by how far its rotation can carry a corner in between.
    Vec3 llo = Vec3::Constant(std::numeric_limits<Real>::max()), lhi = -llo;
    Real reach = 0;  // m, the farthest corner from the mesh's origin
    for (const btTransform& at : {sh.start, sh.pose}) {
      const btTransform inv = at.inverse();
      for (int c = 0; c < 8; ++c) {
        const Vec3 corner((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z());
        const Vec3 q = to_vec(inv * to_bt(corner));
        llo = llo.cwiseMin(q);
        lhi = lhi.cwiseMax(q);
        reach = std::max(reach, q.norm());
      }
    }
    const Real pad = dt * sh.w.norm() * reach;
    llo.array() -= pad;
    lhi.array() += pad;
    detail::collect_mesh_features(static_cast<const btConcaveShape&>(shape), llo, lhi, cs.feature_spacing,
                                  fs.mesh_tris, features);
    // A mesh has no inside to take a side from (a fast feature found over
    // a triangle keeps its own side; see try_triangle).
    centres.assign(features.size(), Vec3::Constant(std::numeric_limits<Real>::quiet_NaN()));
  }
  if (features.empty()) return;
  const btTransform start = sh.start;
  const Vec3 vb = sh.v;
  // Speed gained over the step from the body's forces (m/s, rad/s).
  const Real ab = dt * sh.accel.norm();
  const Real wb = sh.w.norm() + dt * sh.ang_accel.norm();
  int feature_contacts = 0;  // of the feature being tested
  // Continuous collision for features that move farther than the
  // thickness in the step: each one's path over the step, as the body's
  // screw motion cut into `pieces` of turn phi <= sqrt(thickness / (2 r))
  // each, whose chords then stay within a sixteenth of the thickness of
  // the arc (sagitta r phi^2 / 8).
  const Real fast_from = std::max(cs.thickness, Real(1e-3));
  Real r_max = 0;
  for (const Vec3& local : features) r_max = std::max(r_max, local.norm());
  // Clamped before the cast: a huge spin (or a NaN) must not overflow it.
  const Real want = std::ceil(dt * wb * std::sqrt(r_max / (Real(0.5) * fast_from)));
  const int pieces = want >= Real(1) ? (want < Real(kSweepPieces) ? static_cast<int>(want) : kSweepPieces) : 1;
  std::vector<btTransform>& path_tf = fs.path_tf;
  path_tf.clear();
  const bool fast = dt * (vb.norm() + ab + wb * r_max) > fast_from;
  if (fast && cs.edge_contacts && !mesh) {
    // A fast body's box edges get their points along them back: the edge
    // contacts are found at the step's start only, and those points are
    // swept along the path (a spinning blade), or found within their
    // travel. r_max stays: a box's farthest point from the body's origin
    // is a corner.
    features.clear();
    centres.clear();
    detail::collect_features(shape, btTransform::getIdentity(), cs.feature_spacing, features, true, &centres);
  }
  if (fast && cs.sweep_features) {
    const btVector3 v_mean = to_bt(vb + Real(0.5) * dt * sh.accel), w_mean = to_bt(sh.w + Real(0.5) * dt * sh.ang_accel);
    for (int p = 0; p <= pieces; ++p) {
      btTransform at;
      btTransformUtil::integrateTransform(start, v_mean, w_mean, dt * btScalar(p) / btScalar(pieces), at);
      path_tf.push_back(at);
    }
  }
  // Feature at q0 (start of the step) that may travel `travel`, against
  // triangle t, whose grown swept box it reaches (the caller tests that,
  // `outside`): the exact tests, then the contact. path: the feature's
  // path (pieces + 1 points) when it is fast, else null; centre: a point
  // inside its shape (its vertices' mean; NaN for a mesh).
  auto try_triangle = [&](const Vec3& local, const Vec3& q0, Real travel, std::size_t t, const Vec3* path,
                          const Vec3& centre) {
    // At most kFeatureTriangles contacts per feature and step (the first
    // found): a feature rests on a few triangles; more means a thickness
    // far beyond the cloth's triangles (a fuzzed scene with 5 m made
    // 470,000 contacts per step, and its sweeps took 190 ms per frame).
    if (feature_contacts == kFeatureTriangles) return;
    const auto& tri = tris[t];
    const Vec3 x1 = st.x[tri[0]], e1 = st.x[tri[1]] - x1, e2 = st.x[tri[2]] - x1;
    const Vec3 nn = e1.cross(e2);
    const Real a2 = nn.squaredNorm();
    if (!(a2 > Real(0))) return;
    // Barycentric coordinates of the feature's projection: it must lie
    // over the triangle (with a margin of one feature spacing relative to
    // the triangle size, so a corner over a shared edge hits both sides).
    const Vec3 d = q0 - x1;
    const Real u = d.cross(e2).dot(nn) / a2;  // weight of x2
    const Real v = e1.cross(d).dot(nn) / a2;  // weight of x3
    const Real tol = Real(0.05);
    const bool over = !(u < -tol || v < -tol || u + v > Real(1) + tol);
    if (!over && path == nullptr) return;
    const Real dist = d.dot(nn) / std::sqrt(a2);
    Real r = 0;
    for (Index p : tri) r = std::max(r, m.radius[p]);
    const Real thick = r + cs.thickness;
    Real move = travel;
    for (Index p : tri) move = std::max(move, dt * ((st.v[p] - vb).norm() + ab));
    Real side = dist >= Real(0) ? Real(1) : Real(-1);
    bool swept = false;
    if (over && std::abs(dist) <= thick && centre.allFinite()) {
      // A feature found over the triangle, within the band: it belongs on
      // the side of its shape's centre. On the other side it has gone
      // through (a thin blade's edge through a cloth it sweeps under, or a
      // corner through a face in an earlier step), and the contact pushes
      // the triangle back over it, not on through. (The centre and the
      // feature on two sides of the plane, the feature within the band
      // over the triangle: the triangle cuts the convex shape between the
      // two, in all but very oblique cases.) Farther than the band, the
      // side the feature is on holds. A mesh's features have no centre.
      side = (centre - x1).dot(nn) >= Real(0) ? Real(1) : Real(-1);
    }
    if (!over || std::abs(dist) > thick + cs.margin + move) {
      // Not over the triangle at the start, or not near it: a fast
      // feature still gets the contact if its path enters the band over
      // the triangle during the step.
      if (path == nullptr) return;
      // The path's box (its pieces' chords lie in it, padded by the
      // chords' distance from the arc) against the triangle's grown
      // swept box first: most candidates end there.
      const Real pad = Real(0.25) * fast_from;
      if ((path_lo.array() - pad > tri_hi_[t].array()).any() || (path_hi.array() + pad < tri_lo_[t].array()).any())
        return;
      const std::array<Vec3, 3> from{st.x[tri[0]], st.x[tri[1]], st.x[tri[2]]};
      const std::array<Vec3, 3> to{from[0] + dt * st.v[tri[0]], from[1] + dt * st.v[tri[1]],
                                   from[2] + dt * st.v[tri[2]]};
      if (!detail::sweep_reaches_triangle(path, pieces + 1, from, to, dist >= Real(0) ? Real(1) : Real(-1), dist,
                                          thick + cs.margin))
        return;
      swept = true;
    }
    if (++feature_contacts == kFeatureTriangles) ++out.capped;
    if (swept) ++out.swept;
    xpbd::BodyTriangleContact c;  // body: set when joined (step_system)
    c.r = local;
    c.tri = tri;
    c.side = side;
    c.thickness = thick;
    // Acts within the margin behind the plane, plus a substep's closing in
    // (the relative travel the feature was found with, over the step).
    c.reach = cs.margin;
    c.closing_speed = move / dt;
    // Combined with the body's friction by product, as particle contacts.
    c.static_friction = cs.static_friction * obj->getFriction();
    c.dynamic_friction = cs.dynamic_friction * obj->getFriction();
    out.triangle.push_back(c);
  };
  // The hierarchy holds the grown boxes the test `outside` reads, so a
  // query over a feature's box grown by its travel returns every triangle
  // that test passes (rounding is monotone); the small pad is a margin on
  // top, so the hierarchy never drops a triangle the loop over all of them
  // would test.
  auto pad_of = [](const Vec3& q, Real reach) {
    return Real(1e-5) * (q.cwiseAbs().maxCoeff() + reach) + std::numeric_limits<Real>::min();
  };
  // With the hierarchy, first the triangles near the body's features as a
  // whole (one query); a feature then tests those of its grid cell, in
  // ascending order as the loop does, or, when they are many (a body under
  // much of the cloth), queries the hierarchy itself.
  // The features at the start of the step and how far they can move.
  const std::size_t nf = features.size();
  std::vector<Vec3>& feature_at = fs.feature_at;
  std::vector<Real>& feature_travel = fs.feature_travel;
  feature_at.resize(nf);
  feature_travel.resize(nf);
  for (std::size_t i = 0; i < nf; ++i) {
    feature_at[i] = to_vec(start * to_bt(features[i]));
    feature_travel[i] = dt * (vb.norm() + ab + wb * features[i].norm());
  }
  bool per_feature = false, few = false;
  if (use_bvh) {
    Vec3 flo = Vec3::Constant(std::numeric_limits<Real>::max()), fhi = -flo;
    Real reach = 0;
    for (std::size_t i = 0; i < nf; ++i) {
      flo = flo.cwiseMin(feature_at[i]);
      fhi = fhi.cwiseMax(feature_at[i]);
      reach = std::max(reach, feature_travel[i]);
    }
    const Real pad = pad_of(flo.cwiseAbs().cwiseMax(fhi.cwiseAbs()), reach);
    fs.body_tris.clear();
    s.tri_bvh->query((flo.array() - (reach + pad)).matrix(), (fhi.array() + (reach + pad)).matrix(), fs.body_tris,
                      fs.tri_marks);
    // The body's triangles' boxes by coordinate: each feature tests them
    // all when that is few tests.
    fs.boxes.assign(fs.body_tris, tri_lo_, tri_hi_);
    few = nf * fs.body_tris.size() <= kBruteTests;
    per_feature = !few && fs.body_tris.size() > kBodyTriangles;
    if (!few && !per_feature) {
      // The body's triangles in a grid over its features: a triangle is in
      // every cell its box, grown by the features' largest travel, meets;
      // so the cell of a feature holds every triangle its own box test
      // below can pass, in ascending order (the contacts are those of the
      // loop, in its order).
      Real side = 0;
      for (const int t : fs.body_tris) side += (tri_hi_[std::size_t(t)] - tri_lo_[std::size_t(t)]).maxCoeff();
      side *= kCellPerTriangle / Real(std::max<std::size_t>(fs.body_tris.size(), 1));
      fs.grid.build(flo, fhi, side, reach + pad, fs.body_tris, tri_lo_, tri_hi_);
    }
  }
  for (std::size_t i = 0; i < nf; ++i) {
    const Vec3& local = features[i];
    feature_contacts = 0;
    // The feature at the start of the step and where it moves over the step.
    const Vec3 q0 = feature_at[i];
    const Real travel = feature_travel[i];
    if ((q0.array() + travel < lo.array()).any() || (q0.array() - travel > hi.array()).any())
      continue;
    const Vec3* path = nullptr;
    // A point inside the feature's shape at the start of the step (NaN for a mesh).
    const Vec3 centre = centres[i].allFinite() ? to_vec(start * to_bt(centres[i])) : centres[i];
    if (!path_tf.empty() && travel > fast_from) {
      path_lo = Vec3::Constant(std::numeric_limits<Real>::max());
      path_hi = -path_lo;
      for (int k = 0; k <= pieces; ++k) {
        const Vec3 q = to_vec(path_tf[std::size_t(k)] * to_bt(local));
        path_at[std::size_t(k)] = q;
        path_lo = path_lo.cwiseMin(q);
        path_hi = path_hi.cwiseMax(q);
      }
      path = path_at.data();
    }
    if (!use_bvh) {
      for (std::size_t t = 0; t < tris.size(); ++t)
        if (!outside(q0, travel, tri_lo_[t], tri_hi_[t])) try_triangle(local, q0, travel, t, path, centre);
    } else if (few) {
      fs.tri_found.clear();
      fs.boxes.overlapping((q0.array() - travel).matrix(), (q0.array() + travel).matrix(), fs.tri_found);
      for (const int j : fs.tri_found)
        try_triangle(local, q0, travel, std::size_t(fs.body_tris[std::size_t(j)]), path, centre);
    } else if (!per_feature) {
      const auto [near, near_end] = fs.grid.near(q0);
      for (const int* t = near; t != near_end; ++t)
        if (!outside(q0, travel, tri_lo_[std::size_t(*t)], tri_hi_[std::size_t(*t)]))
          try_triangle(local, q0, travel, std::size_t(*t), path, centre);
    } else {
      const Real reach = travel, pad = pad_of(q0, reach);
      fs.tri_found.clear();
      s.tri_bvh->query((q0.array() - (reach + pad)).matrix(), (q0.array() + (reach + pad)).matrix(), fs.tri_found,
                        fs.tri_marks);
      for (const int t : fs.tri_found)
        if (!outside(q0, travel, tri_lo_[std::size_t(t)], tri_hi_[std::size_t(t)]))
          try_triangle(local, q0, travel, std::size_t(t), path, centre);
    }
  }
}

}  // namespace xpbd_bullet
