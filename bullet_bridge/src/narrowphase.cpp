// Particle-vs-rigid contact queries (see xpbd_bullet/narrowphase.hpp).
//
// Who answers which query, and why (docs/design.md section 4, docs/collision-queries.md):
//
// | shape                                   | distance (query_point)                   | sweep (sweep_point)                     |
// |-----------------------------------------|------------------------------------------|-----------------------------------------|
// | btSphereShape                           | closed form                              | closed form (ray-sphere)                |
// | btBoxShape                              | closed form (nearest face inside)        | closed form (slabs)                     |
// | btCapsuleShape / X / Z                  | closed form (segment distance - radius)  | root of the convex closed-form distance |
// | btCylinderShape / X / Z                 | closed form (2-D box in r, axial)        | root of the convex closed-form distance |
// | btStaticPlaneShape                      | closed form (half-space below the plane) | closed form                             |
// | other btConvexShape (hull, cone, ...)   | btGjkEpaSolver2: GJK out, EPA inside     | root of the GJK/EPA distance            |
// | btCompoundShape                         | children, smallest distance wins         | children, smallest fraction wins        |
// | btConcaveShape with triangles (BVH mesh,| processAllTriangles over the query box,  | processAllTriangles over the segment    |
// |  scaled BVH mesh, heightfield)          | one-sided closest point (own code)       | box, one-sided ray-triangle (own code)  |
//
// The triangle callbacks are in narrowphase_triangles.cpp, the GJK/EPA
// signed distance in narrowphase_convex.cpp (narrowphase_internal.hpp).
//
// FCL is not used here: its signed distance for primitives runs libccd GJK/EPA
// (approximate inside curved shapes, wrong for a zero-radius sphere outside a
// box, a crash against a half-space), its sphere-capsule contact has no normal
// on the axis, and its sphere-triangle contact is two-sided with a negative
// depth (fcl PR #569). tests/bridge/test_narrowphase_fcl.cpp shows each.
#include "xpbd_bullet/narrowphase.hpp"

#include "narrowphase_internal.hpp"

#include <btBulletCollisionCommon.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace xpbd_bullet {
namespace {

using namespace narrowphase;

static_assert(std::is_same_v<btScalar, xpbd::Real>,
              "the bridge must link the Bullet build whose btScalar is xpbd::Real");

using xpbd::Real;
using xpbd::Vec3;

std::string fmt(const Vec3& v) {
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

void require_finite(const char* fn, const char* name, const Vec3& v) {
  if (!v.allFinite())
    throw std::invalid_argument(std::string(fn) + ": " + name + " = " + fmt(v) + " is not finite");
}

// A unit vector perpendicular to axis `up` (0, 1, 2): the next axis. Used where
// the nearest direction is not unique (a point on a capsule's axis).
Vec3 perpendicular_axis(int up) { return Vec3::Unit((up + 1) % 3); }

// ---------------------------------------------------------------------------
// Closed forms in the shape's local frame. Each returns the closest surface
// point, the outward unit normal and the signed distance of p, with
// p == point + distance * normal.
// ---------------------------------------------------------------------------

Local sphere_local(Real radius, const Vec3& p) {
  const Real r = p.norm();
  // At the centre every direction is nearest; pick +Y.
  const Vec3 n = r > tol_at(p) ? Vec3(p / r) : Vec3::UnitY();
  return {radius * n, n, r - radius};
}

// Box of half extents h centred at the origin. Outside: distance to the
// clamped point. Inside: the nearest face (largest of |p_i| - h_i), so the
// depth is exact and the normal is that face's normal.
Local box_local(const Vec3& h, const Vec3& p) {
  const Vec3 q = p.cwiseAbs() - h;  // per-axis signed slab distance
  if ((q.array() > 0).any()) {
    const Vec3 c = p.cwiseMax(-h).cwiseMin(h);
    const Vec3 d = p - c;
    const Real len = d.norm();
    return {c, d / len, len};
  }
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (q[i] > q[axis]) axis = i;
  const Real s = p[axis] >= 0 ? Real(1) : Real(-1);
  Vec3 c = p;
  c[axis] = s * h[axis];
  return {c, s * Vec3::Unit(axis), q[axis]};
}

// Capsule: segment from -H to +H along axis `up`, radius R.
Local capsule_local(int up, Real radius, Real half_height, const Vec3& p) {
  Vec3 s = Vec3::Zero();
  s[up] = std::clamp(p[up], -half_height, half_height);  // closest point on the core segment
  const Vec3 d = p - s;
  const Real len = d.norm();
  const Vec3 n = len > tol_at(p) ? Vec3(d / len) : perpendicular_axis(up);
  return {s + radius * n, n, len - radius};
}

// Cylinder of radius R and half height H along axis `up`. In the coordinates
// (radial distance r, axial a) it is a 2-D box of half extents (R, H):
// dr = r - R, da = |a| - H.
Local cylinder_local(int up, Real radius, Real half_height, const Vec3& p) {
  Vec3 radial = p;
  radial[up] = 0;
  const Real r = radial.norm();
  const Real a = p[up];
  const Real sa = a >= 0 ? Real(1) : Real(-1);
  const Vec3 axis = Vec3::Unit(up);
  // Radial unit vector; on the axis every radial direction is nearest.
  const Vec3 er = r > tol_at(p) ? Vec3(radial / r) : perpendicular_axis(up);
  const Real dr = r - radius;
  const Real da = std::abs(a) - half_height;
  if (dr > 0 && da > 0) {  // outside the rim: closest point on the circular edge
    const Vec3 c = sa * half_height * axis + radius * er;
    const Vec3 d = p - c;
    const Real len = d.norm();
    return {c, d / len, len};
  }
  if (dr > da) {  // barrel nearest (outside beside it, or inside nearer the barrel)
    return {a * axis + radius * er, er, dr};
  }
  // cap nearest (outside above/below it, or inside nearer the cap)
  return {radial + sa * half_height * axis, sa * axis, da};
}

// Half-space n.x <= c of a static plane (n unit): signed distance n.p - c.
Local plane_local(const Vec3& n, Real c, const Vec3& p) {
  const Real d = n.dot(p) - c;
  return {p - d * n, n, d};
}

// ---------------------------------------------------------------------------
// Shape dispatch
// ---------------------------------------------------------------------------
enum class Kind { Sphere, Box, Capsule, Cylinder, Plane, Convex, Compound, Triangles, Unsupported };

Kind kind_of(const btCollisionShape& shape) {
  switch (shape.getShapeType()) {
    case SPHERE_SHAPE_PROXYTYPE: return Kind::Sphere;
    case BOX_SHAPE_PROXYTYPE: return Kind::Box;
    case CAPSULE_SHAPE_PROXYTYPE: return Kind::Capsule;
    case CYLINDER_SHAPE_PROXYTYPE: return Kind::Cylinder;
    case STATIC_PLANE_PROXYTYPE: return Kind::Plane;
    case COMPOUND_SHAPE_PROXYTYPE: return Kind::Compound;
    case TRIANGLE_MESH_SHAPE_PROXYTYPE:
    case SCALED_TRIANGLE_MESH_SHAPE_PROXYTYPE:
    case MULTIMATERIAL_TRIANGLE_MESH_PROXYTYPE:
    case TERRAIN_SHAPE_PROXYTYPE: return Kind::Triangles;
    default: break;
  }
  if (shape.isConvex()) return Kind::Convex;
  return Kind::Unsupported;
}

// Closed-form distance of a local point for the primitive kinds.
Local primitive_local(Kind kind, const btCollisionShape& shape, const Vec3& p) {
  switch (kind) {
    case Kind::Sphere: return sphere_local(static_cast<const btSphereShape&>(shape).getRadius(), p);
    case Kind::Box:
      return box_local(to_vec(static_cast<const btBoxShape&>(shape).getHalfExtentsWithMargin()), p);
    case Kind::Capsule: {
      const auto& s = static_cast<const btCapsuleShape&>(shape);
      return capsule_local(s.getUpAxis(), s.getRadius(), s.getHalfHeight(), p);
    }
    case Kind::Cylinder: {
      // Bullet's cylinder is circular with radius getRadius() (the half extent
      // of the first radial axis); the half height is the up-axis half extent.
      const auto& s = static_cast<const btCylinderShape&>(shape);
      const int up = s.getUpAxis();
      return cylinder_local(up, s.getRadius(), s.getHalfExtentsWithMargin()[up], p);
    }
    case Kind::Plane: {
      const auto& s = static_cast<const btStaticPlaneShape&>(shape);
      return plane_local(to_vec(s.getPlaneNormal()), s.getPlaneConstant(), p);
    }
    default: break;
  }
  return {p, Vec3::UnitY(), kInf};  // not reached: callers pass primitive kinds only
}

ParticleContact to_world(const btTransform& t, const Local& l) {
  return {to_vec(t * to_bt(l.point)), to_vec(t.getBasis() * to_bt(l.normal)), l.distance};
}

// Distance from x to the box [lo, hi] (0 inside): a lower bound of the
// distance to any shape inside that box.
Real distance_to_aabb(const Vec3& x, const btVector3& lo, const btVector3& hi) {
  return (x - x.cwiseMax(to_vec(lo)).cwiseMin(to_vec(hi))).norm();
}

bool aabb_far(const btCollisionShape& shape, const btTransform& t, const Vec3& x, Real max_distance) {
  btVector3 lo, hi;
  shape.getAabb(t, lo, hi);
  return distance_to_aabb(x, lo, hi) > max_distance;
}

bool query_shape(const btCollisionShape& shape, const btTransform& t, const Vec3& x, Real max_distance,
                 ParticleContact& out) {
  const Kind kind = kind_of(shape);
  switch (kind) {
    case Kind::Sphere:
    case Kind::Box:
    case Kind::Capsule:
    case Kind::Cylinder:
    case Kind::Plane: {
      const Local l = primitive_local(kind, shape, to_vec(t.invXform(to_bt(x))));
      if (l.distance > max_distance) return false;
      out = to_world(t, l);
      return true;
    }
    case Kind::Convex: {
      if (aabb_far(shape, t, x, max_distance)) return false;
      Local l;
      if (!convex_signed_distance(static_cast<const btConvexShape&>(shape), t, x, l)) return false;
      if (l.distance > max_distance) return false;
      out = {l.point, l.normal, l.distance};
      return true;
    }
    case Kind::Compound: {
      if (aabb_far(shape, t, x, max_distance)) return false;
      const auto& c = static_cast<const btCompoundShape&>(shape);
      bool found = false;
      ParticleContact child_hit;
      for (int i = 0; i < c.getNumChildShapes(); ++i) {
        if (!query_shape(*c.getChildShape(i), t * c.getChildTransform(i), x, max_distance, child_hit))
          continue;
        if (!found || child_hit.distance < out.distance) out = child_hit;
        found = true;
      }
      return found;
    }
    case Kind::Triangles: {
      const Vec3 p = to_vec(t.invXform(to_bt(x)));
      const Vec3 r = Vec3::Constant(max_distance);
      NearestTriangle cb(p, max_distance, front_axis(shape));
      static_cast<const btConcaveShape&>(shape).processAllTriangles(&cb, to_bt(p - r), to_bt(p + r));
      if (!cb.found()) return false;
      out = to_world(t, cb.result());
      return true;
    }
    case Kind::Unsupported: break;
  }
  return false;
}

// ---------------------------------------------------------------------------
// Sweeps
// ---------------------------------------------------------------------------

// First t in [0, 1] with f(t) <= 0 for f(t) = signed distance of a + t (b - a)
// from a CONVEX shape. f is then a convex function of t, Lipschitz with
// constant L = |b - a| (the distance's gradient has unit length), so
//   - {t : f(t) <= 0} is an interval: if f(lo) > 0 >= f(hi), the first root
//     is the only one in (lo, hi], found by bisection;
//   - if both ends are positive, a golden-section search for the minimum
//     looks for a point with f <= 0, and stops as soon as the Lipschitz bound
//     min f >= (f(lo) + f(hi) - (hi - lo) L) / 2 on the bracket proves a miss.
// sd(p, value) evaluates the distance; it returns false if it cannot.
template <class SignedDistance>
bool first_root_convex(SignedDistance&& sd, const Vec3& a, const Vec3& b, Real& t_hit) {
  const Vec3 d = b - a;
  const Real len = d.norm();
  const Real tol = tol_at(a.cwiseAbs().cwiseMax(b.cwiseAbs()));  // m, accuracy of the hit point
  auto f = [&](Real t, Real& v) { return sd(Vec3(a + t * d), v); };
  Real f0, f1;
  if (!f(0, f0)) return false;
  if (f0 <= 0) {
    t_hit = 0;
    return true;
  }
  if (!f(1, f1)) return false;
  if (f0 + f1 - len > 0) return false;  // cannot reach the surface (Lipschitz)
  Real lo = 0, flo = f0, hi = 1, fhi = f1;
  if (fhi > 0) {
    // Golden-section search on [x0, x3] with interior points x1 < x2.
    const Real g = Real(0.5) * (std::sqrt(Real(5)) - 1);
    Real x0 = 0, x3 = 1, v0 = f0, v3 = f1;
    Real x1 = x3 - g * (x3 - x0), x2 = x0 + g * (x3 - x0), v1, v2;
    if (!f(x1, v1) || !f(x2, v2)) return false;
    bool found = false;
    for (int it = 0; it < 200; ++it) {
      if (v1 <= 0 || v2 <= 0) {  // a point inside: the first root is left of it
        hi = v1 <= 0 ? x1 : x2;
        fhi = v1 <= 0 ? v1 : v2;
        lo = v1 <= 0 ? x0 : x1;
        flo = v1 <= 0 ? v0 : v1;
        found = true;
        break;
      }
      if (v0 + v3 - (x3 - x0) * len > 0) return false;  // lower bound on the bracket > 0
      if ((x3 - x0) * len <= tol) return false;          // only grazes the surface
      if (v1 < v2) {  // minimum in [x0, x2]
        x3 = x2, v3 = v2, x2 = x1, v2 = v1;
        x1 = x3 - g * (x3 - x0);
        if (!f(x1, v1)) return false;
      } else {  // minimum in [x1, x3]
        x0 = x1, v0 = v1, x1 = x2, v1 = v2;
        x2 = x0 + g * (x3 - x0);
        if (!f(x2, v2)) return false;
      }
    }
    if (!found) return false;
  }
  // Bisection keeps f(lo) > 0 >= f(hi).
  for (int it = 0; it < 200 && (hi - lo) * len > tol; ++it) {
    const Real mid = Real(0.5) * (lo + hi);
    Real fm;
    if (!f(mid, fm)) return false;
    if (fm > 0) lo = mid, flo = fm;
    else hi = mid, fhi = fm;
  }
  // Final linear interpolation of the root inside [lo, hi].
  t_hit = std::clamp(lo + (hi - lo) * flo / (flo - fhi), lo, hi);
  return true;
}

// Closed-form first entry of the segment p(t) = a + t d into a sphere, for a
// outside: the smaller root of |a + t d|^2 = R^2.
bool sweep_sphere_local(Real radius, const Vec3& a, const Vec3& d, Real& t) {
  const Real A = d.squaredNorm(), B = a.dot(d), C = a.squaredNorm() - radius * radius;
  if (A == 0) return false;
  const Real disc = B * B - A * C;
  if (disc < 0) return false;
  t = (-B - std::sqrt(disc)) / A;
  return t >= 0 && t <= 1;
}

// Slab method: the segment is inside slab i for t in [t_in_i, t_out_i]; it
// enters the box at the largest t_in, if that comes before the smallest t_out.
bool sweep_box_local(const Vec3& h, const Vec3& a, const Vec3& d, Real& t, int& axis) {
  Real t_in = -kInf, t_out = kInf;
  axis = -1;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0) {
      if (std::abs(a[i]) > h[i]) return false;  // parallel to the slab and outside it
      continue;
    }
    Real t0 = (-h[i] - a[i]) / d[i], t1 = (h[i] - a[i]) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_in) t_in = t0, axis = i;
    t_out = std::min(t_out, t1);
  }
  if (axis < 0 || t_in > t_out) return false;
  t = t_in;
  return t >= 0 && t <= 1;
}

bool sweep_shape(const btCollisionShape& shape, const btTransform& tr, const Vec3& a, const Vec3& b,
                 ParticleContact& out, Real& t);

// Result of a hit at fraction t on a closed convex shape: the contact of the
// hit point, and the end point's distance from the tangent plane there.
void finish_hit(ParticleContact& out, const Vec3& b) { out.distance = (b - out.point).dot(out.normal); }

bool sweep_primitive(Kind kind, const btCollisionShape& shape, const btTransform& tr, const Vec3& a,
                     const Vec3& b, ParticleContact& out, Real& t) {
  const Vec3 la = to_vec(tr.invXform(to_bt(a))), lb = to_vec(tr.invXform(to_bt(b)));
  const Vec3 ld = lb - la;
  const Local start = primitive_local(kind, shape, la);
  if (start.distance <= 0) {  // starts inside or on the surface
    t = 0;
    out = to_world(tr, start);
    finish_hit(out, b);
    return true;
  }
  Local hit;
  switch (kind) {
    case Kind::Sphere: {
      const Real radius = static_cast<const btSphereShape&>(shape).getRadius();
      if (!sweep_sphere_local(radius, la, ld, t)) return false;
      const Vec3 n = (la + t * ld) / radius;
      hit = {radius * n, n, 0};
      break;
    }
    case Kind::Box: {
      const Vec3 h = to_vec(static_cast<const btBoxShape&>(shape).getHalfExtentsWithMargin());
      int axis;
      if (!sweep_box_local(h, la, ld, t, axis)) return false;
      Vec3 p = la + t * ld;
      const Real s = ld[axis] < 0 ? Real(1) : Real(-1);  // the face the segment enters through
      p[axis] = s * h[axis];
      hit = {p, s * Vec3::Unit(axis), 0};
      break;
    }
    case Kind::Plane: {
      const Local end = primitive_local(kind, shape, lb);
      if (end.distance > 0) return false;
      t = start.distance / (start.distance - end.distance);
      hit = primitive_local(kind, shape, la + t * ld);
      break;
    }
    default: {  // capsule, cylinder: convex closed-form distance
      auto sd = [&](const Vec3& p, Real& v) {
        v = primitive_local(kind, shape, p).distance;
        return true;
      };
      if (!first_root_convex(sd, la, lb, t)) return false;
      hit = primitive_local(kind, shape, la + t * ld);
      break;
    }
  }
  out = to_world(tr, hit);
  out.distance = 0;
  finish_hit(out, b);
  return true;
}

bool sweep_shape(const btCollisionShape& shape, const btTransform& tr, const Vec3& a, const Vec3& b,
                 ParticleContact& out, Real& t) {
  const Kind kind = kind_of(shape);
  switch (kind) {
    case Kind::Sphere:
    case Kind::Box:
    case Kind::Capsule:
    case Kind::Cylinder:
    case Kind::Plane: return sweep_primitive(kind, shape, tr, a, b, out, t);
    case Kind::Convex: {
      btVector3 lo, hi;
      shape.getAabb(tr, lo, hi);
      const Vec3 slo = a.cwiseMin(b), shi = a.cwiseMax(b);
      if ((slo.array() > to_vec(hi).array()).any() || (shi.array() < to_vec(lo).array()).any()) return false;
      const auto& convex = static_cast<const btConvexShape&>(shape);
      Local l;
      auto sd = [&](const Vec3& p, Real& v) {
        if (!convex_signed_distance(convex, tr, p, l)) return false;
        v = l.distance;
        return true;
      };
      if (!first_root_convex(sd, a, b, t)) return false;
      if (!convex_signed_distance(convex, tr, Vec3(a + t * (b - a)), l)) return false;
      out = {l.point, l.normal, 0};
      finish_hit(out, b);
      return true;
    }
    case Kind::Compound: {
      const auto& c = static_cast<const btCompoundShape&>(shape);
      bool found = false;
      ParticleContact child_hit;
      Real child_t;
      for (int i = 0; i < c.getNumChildShapes(); ++i) {
        if (!sweep_shape(*c.getChildShape(i), tr * c.getChildTransform(i), a, b, child_hit, child_t)) continue;
        if (!found || child_t < t) out = child_hit, t = child_t;
        found = true;
      }
      return found;
    }
    case Kind::Triangles: {
      const Vec3 la = to_vec(tr.invXform(to_bt(a))), lb = to_vec(tr.invXform(to_bt(b)));
      FirstTriangleHit cb(la, lb, front_axis(shape));
      static_cast<const btConcaveShape&>(shape).processAllTriangles(&cb, to_bt(la.cwiseMin(lb)),
                                                                    to_bt(la.cwiseMax(lb)));
      if (!cb.hit()) return false;
      t = cb.t();
      out = to_world(tr, {la + t * (lb - la), cb.normal(), 0});
      finish_hit(out, b);
      return true;
    }
    case Kind::Unsupported: break;
  }
  return false;
}

bool object_has_contacts(const btCollisionObject& obj) {
  const int type = obj.getInternalType();
  const bool rigid_like = type == btCollisionObject::CO_COLLISION_OBJECT ||
                          type == btCollisionObject::CO_RIGID_BODY ||
                          type == btCollisionObject::CO_FEATHERSTONE_LINK;
  return rigid_like && obj.hasContactResponse() && obj.getCollisionShape() &&
         is_supported(*obj.getCollisionShape());
}

// Collects the proxies of aabbTest whose exact AABB overlaps the query box
// (btDbvtBroadphase reports leaves of its fattened tree, a superset).
class AabbCollector : public btBroadphaseAabbCallback {
 public:
  AabbCollector(const btVector3& lo, const btVector3& hi, int group, int mask,
                std::vector<const btCollisionObject*>& out)
      : lo_(lo), hi_(hi), group_(group), mask_(mask), out_(out) {}

  bool process(const btBroadphaseProxy* proxy) override {
    for (int i = 0; i < 3; ++i)
      if (proxy->m_aabbMin[i] > hi_[i] || proxy->m_aabbMax[i] < lo_[i]) return true;
    if ((proxy->m_collisionFilterGroup & mask_) == 0 || (group_ & proxy->m_collisionFilterMask) == 0)
      return true;
    const auto* obj = static_cast<const btCollisionObject*>(proxy->m_clientObject);
    if (obj && object_has_contacts(*obj)) out_.push_back(obj);
    return true;  // keep traversing
  }

 private:
  btVector3 lo_, hi_;
  int group_, mask_;
  std::vector<const btCollisionObject*>& out_;
};

}  // namespace

bool is_supported(const btCollisionShape& shape) {
  const Kind kind = kind_of(shape);
  if (kind != Kind::Compound) return kind != Kind::Unsupported;
  // A compound is supported if any child is; unsupported children are skipped.
  const auto& c = static_cast<const btCompoundShape&>(shape);
  for (int i = 0; i < c.getNumChildShapes(); ++i)
    if (is_supported(*c.getChildShape(i))) return true;
  return false;
}

bool query_point(const btCollisionObject& obj, const Vec3& x, Real max_distance, ParticleContact& out) {
  require_finite("query_point", "x", x);
  if (!(max_distance >= 0) || !std::isfinite(max_distance)) {
    std::ostringstream s;
    s << "query_point: max_distance = " << max_distance << " must be finite and >= 0 (m)";
    throw std::invalid_argument(s.str());
  }
  if (!obj.getCollisionShape() || obj.getInternalType() == btCollisionObject::CO_SOFT_BODY) return false;
  return query_shape(*obj.getCollisionShape(), obj.getWorldTransform(), x, max_distance, out);
}

void candidates(btCollisionWorld& world, const Vec3& lo, const Vec3& hi,
                std::vector<const btCollisionObject*>& out, int filter_group, int filter_mask) {
  require_finite("candidates", "lo", lo);
  require_finite("candidates", "hi", hi);
  for (int i = 0; i < 3; ++i)
    if (lo[i] > hi[i])
      throw std::invalid_argument("candidates: lo = " + fmt(lo) + " exceeds hi = " + fmt(hi) + " on axis " +
                                  std::to_string(i));
  out.clear();
  AabbCollector cb(to_bt(lo), to_bt(hi), filter_group, filter_mask, out);
  world.getBroadphase()->aabbTest(to_bt(lo), to_bt(hi), cb);
}

namespace detail {

// Declared in world_impl.hpp (XpbdWorld's contact search).
bool is_primitive(const btCollisionShape& shape) {
  switch (kind_of(shape)) {
    case Kind::Sphere:
    case Kind::Box:
    case Kind::Capsule:
    case Kind::Cylinder:
    case Kind::Plane: return true;
    default: return false;
  }
}

bool query_primitive_local(const btCollisionShape& shape, const Vec3& p, Real max_distance, ParticleContact& out) {
  const Local l = primitive_local(kind_of(shape), shape, p);
  if (l.distance > max_distance) return false;
  out = {l.point, l.normal, l.distance};
  return true;
}

void add_moving_candidates(btCollisionWorld& world, const Vec3& lo, const Vec3& hi, Real dt, int filter_group,
                           int filter_mask, std::vector<const btCollisionObject*>& out) {
  const btCollisionObjectArray& objects = world.getCollisionObjectArray();
  for (int i = 0; i < objects.size(); ++i) {
    const btCollisionObject* obj = objects[i];
    const btRigidBody* rb = btRigidBody::upcast(obj);
    if (rb == nullptr || rb->isStaticObject()) continue;  // dynamic and kinematic bodies move
    const btBroadphaseProxy* proxy = obj->getBroadphaseHandle();
    if (proxy == nullptr || (proxy->m_collisionFilterGroup & filter_mask) == 0 ||
        (filter_group & proxy->m_collisionFilterMask) == 0 || !object_has_contacts(*obj))
      continue;
    btVector3 amin, amax;
    obj->getCollisionShape()->getAabb(obj->getWorldTransform(), amin, amax);
    const btScalar accel = rb->isStaticOrKinematicObject() ? btScalar(0) : (rb->getTotalForce() * rb->getInvMass()).length();
    const btScalar travel = dt * (rb->getLinearVelocity().length() + dt * accel +
                                  rb->getAngularVelocity().length() * (amax - amin).length());
    if (!(travel > 0)) continue;  // at rest (or not finite: left to the caller's checks)
    bool overlaps = true;
    for (int a = 0; a < 3; ++a)
      if (amin[a] - travel > hi[a] || amax[a] + travel < lo[a]) overlaps = false;
    if (overlaps && std::find(out.begin(), out.end(), obj) == out.end()) out.push_back(obj);
  }
}

}  // namespace detail

bool sweep_point(const btCollisionObject& obj, const Vec3& a, const Vec3& b, ParticleContact& out,
                 Real& fraction) {
  require_finite("sweep_point", "a", a);
  require_finite("sweep_point", "b", b);
  if (!obj.getCollisionShape() || obj.getInternalType() == btCollisionObject::CO_SOFT_BODY) return false;
  return sweep_shape(*obj.getCollisionShape(), obj.getWorldTransform(), a, b, out, fraction);
}

}  // namespace xpbd_bullet
