// Signed distance to a generic convex shape by Bullet's GJK and EPA
// (narrowphase_internal.hpp).
#include <BulletCollision/NarrowPhaseCollision/btGjkEpa2.h>

#include <cmath>
#include <type_traits>

#include "narrowphase_internal.hpp"

namespace xpbd_bullet::narrowphase {
namespace {

// Makes n the outward normal at the surface point w of a convex shape: an
// outward normal supports the shape at w, h(n) = max_y y.n = w.n, while -n
// would give h(-n) = w.(-n) + (width of the shape along n). Bullet 3.24
// reports points within GJK's accuracy outside the surface as penetrating with
// the inward normal: flipping n and the sign of d keeps x = w + d n and gives
// the outward normal. Only used near the surface with EPA's plane normal: the
// test needs an accurate n (a tilt by angle a raises h(n) - w.n by about
// a * the shape's extent, which can exceed the width of a thin shape).
void orient_outward(const btConvexShape& shape, const btTransform& t, Local& l) {
  const btVector3 n = t.getBasis().transpose() * to_bt(l.normal);  // local frame
  const btScalar w = t.invXform(to_bt(l.point)).dot(n);
  const btScalar excess_plus = shape.localGetSupportingVertex(n).dot(n) - w;     // 0 if n is outward
  const btScalar excess_minus = shape.localGetSupportingVertex(-n).dot(-n) + w;  // 0 if -n is outward
  if (excess_minus < excess_plus) {
    l.normal = -l.normal;
    l.distance = -l.distance;
  }
}

// Outside a convex shape GJK's normal is (x - w) / |x - w| with witness
// errors of ~1e-12 m (double; GJK_ACCURACY) or ~1e-3 m (float), so it is
// noisy when x is within a band of kConvexBand (1 + |x|) of the surface.
// There the normal is taken from EPA at a point one band inside instead:
// EPA's normal is the plane of a polytope face, exact for a face. Near an edge
// the inner point may fall nearer to another face; that plane is only taken
// if it is within 60 degrees of GJK's direction (a neighbouring face of the
// same edge or vertex, a valid supporting normal that close to it).
constexpr Real kConvexBand = std::is_same_v<Real, double> ? Real(1e-6) : Real(1e-3);  // relative

// One GJK/EPA signed distance, following btGjkEpaSolver2::SignedDistance but
// keeping EPA's own normal inside (that function replaces it by the difference
// of two witness points, whose round-off dominates at depths near 0):
//  - outside the core shape (margin excluded), GJK gives the closest points
//    w0 (shape) and w1 (= x); the surface with margin m is m further along
//    n = (w1 - w0) / |w1 - w0|, and d = |w1 - w0| - m;
//  - otherwise EPA on the shape with its margin gives the depth, the surface
//    point and the plane normal of the nearest polytope face.
bool convex_signed_distance_raw(const btConvexShape& shape, const btTransform& t, const Vec3& x, Local& out,
                                bool& separated) {
  btSphereShape point(0);  // a sphere of radius 0 has margin 0
  const btTransform at(btQuaternion::getIdentity(), to_bt(x));
  btGjkEpaSolver2::sResults r;
  separated = false;
  if (btGjkEpaSolver2::Distance(&shape, t, &point, at, btVector3(1, 1, 1), r)) {
    const btVector3 delta = r.witnesses[1] - r.witnesses[0];
    const btScalar len = delta.length();
    if (len > 0 && std::isfinite(len)) {
      const btScalar margin = shape.getMargin();
      const btVector3 n = delta / len;
      out = {to_vec(r.witnesses[0] + n * margin), to_vec(n), len - margin};
      separated = true;
    }
  }
  if (!separated) {
    if (!btGjkEpaSolver2::Penetration(&shape, t, &point, at, btVector3(1, 1, 1), r, true)) return false;
    // r.normal is minus EPA's normal, in the shape's frame; r.distance = -depth.
    out = {to_vec(r.witnesses[0]), to_vec(t.getBasis() * (-r.normal)), r.distance};
  }
  return out.point.allFinite() && out.normal.allFinite() && std::isfinite(out.distance);
}

}  // namespace

// Signed distance of a world point to a generic convex shape including its
// margin, by Bullet's GJK (outside) / EPA (inside). Returns false if both fail.
bool convex_signed_distance(const btConvexShape& shape, const btTransform& t, const Vec3& x, Local& out) {
  bool separated;
  if (!convex_signed_distance_raw(shape, t, x, out, separated)) return false;
  const Real band = kConvexBand * (Real(1) + x.cwiseAbs().maxCoeff());
  if (std::abs(out.distance) >= band) return true;  // clearly outside or inside: side and normal are reliable
  if (!separated) {  // EPA at the surface: an accurate plane, possibly on the wrong side
    orient_outward(shape, t, out);
    return true;
  }
  // GJK at the surface: a reliable side, a noisy direction. Take EPA's plane
  // from a point `band` inside (deep enough for EPA's side to be reliable).
  Local inner;
  bool inner_separated;
  const Vec3 x_in = x - (out.distance + band) * out.normal;
  if (convex_signed_distance_raw(shape, t, x_in, inner, inner_separated) && !inner_separated) {
    if (std::abs(inner.distance) < Real(0.5) * band) orient_outward(shape, t, inner);
    if (inner.normal.dot(out.normal) > Real(0.5)) out.normal = inner.normal;
  }
  return true;
}

}  // namespace xpbd_bullet::narrowphase
