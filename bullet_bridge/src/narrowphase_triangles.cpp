// Particle queries against triangle meshes and heightfields
// (narrowphase_internal.hpp).
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>

#include <algorithm>
#include <cmath>

#include "narrowphase_internal.hpp"

namespace xpbd_bullet::narrowphase {
namespace {

// Closest point to p on triangle (a, b, c), by the Voronoi region of p:
// three vertex regions, three edge regions, or the face (Ericson, Real-Time
// Collision Detection, section 5.1.5). Barycentric quantities are written in
// terms of dot products of edge vectors, no normal needed. `in_face` tells
// whether p projects inside the triangle (face region).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, bool& in_face) {
  in_face = false;
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;  // edge ab
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;  // edge ac
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)                     // edge bc
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const Real denom = Real(1) / (va + vb + vc);  // face interior
  in_face = true;
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Unit front normal of a triangle, or zero for a degenerate one. A
// heightfield's front is its up side whatever its winding (up >= 0).
Vec3 front_normal(const Vec3& a, const Vec3& b, const Vec3& c, int up) {
  Vec3 n = (b - a).cross(c - a);
  const Real len = n.norm();
  const Real scale = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
  if (!(len > xpbd::kDegenerateRel * scale)) return Vec3::Zero();
  n /= len;
  if (up >= 0 && n[up] < 0) n = -n;
  return n;
}

}  // namespace

// -1 for meshes (front = counter-clockwise side), the up axis for heightfields.
int front_axis(const btCollisionShape& shape) {
  if (shape.getShapeType() == TERRAIN_SHAPE_PROXYTYPE)
    return static_cast<const btHeightfieldTerrainShape&>(shape).getUpAxis();
  return -1;
}

void NearestTriangle::processTriangle(btVector3* tri, int, int) {
  const Vec3 a = to_vec(tri[0]), b = to_vec(tri[1]), c = to_vec(tri[2]);
  const Vec3 n = front_normal(a, b, c, up_);
  if (n.isZero()) return;  // degenerate triangle: no side, no contact
  bool in_face;
  const Vec3 q = closest_on_triangle(x_, a, b, c, in_face);
  const Real d = (x_ - q).norm();
  if (d > max_d_) return;
  // How squarely the triangle's plane faces x: 1 in the face region.
  const Real facing = d > tol_ ? std::abs((x_ - q).dot(n)) / d : Real(1);
  if (found_ && !(d < best_d_ - tol_ || (d <= best_d_ + tol_ && facing > best_facing_))) return;
  found_ = true;
  best_d_ = d;
  best_facing_ = facing;
  best_q_ = q;
  best_n_ = n;
  best_in_face_ = in_face;
}

Local NearestTriangle::result() const {
  const Vec3 d = x_ - best_q_;
  if (best_d_ <= tol_) return {best_q_, best_n_, 0};
  // Face region: x - q is parallel to the normal up to the round-off of q,
  // which (x - q) / |x - q| would amplify for tiny distances; the face
  // normal and the plane distance are exact there.
  if (best_in_face_) return {best_q_, best_n_, d.dot(best_n_)};
  const Real side = d.dot(best_n_) >= 0 ? Real(1) : Real(-1);
  return {best_q_, side * d / best_d_, side * best_d_};
}

void FirstTriangleHit::processTriangle(btVector3* tri, int, int) {
  const Vec3 v0 = to_vec(tri[0]), v1 = to_vec(tri[1]), v2 = to_vec(tri[2]);
  const Vec3 n = front_normal(v0, v1, v2, up_);
  if (n.isZero() || d_.dot(n) >= 0) return;
  const Vec3 e1 = v1 - v0, e2 = v2 - v0;
  const Vec3 pv = d_.cross(e2);
  const Real det = e1.dot(pv);
  if (det == 0) return;  // segment parallel to the plane (d . n < 0 makes this rare)
  const Real inv = Real(1) / det;
  const Vec3 tv = a_ - v0;
  const Real u = tv.dot(pv) * inv;
  const Vec3 qv = tv.cross(e1);
  const Real v = d_.dot(qv) * inv;
  const Real t = e2.dot(qv) * inv;
  // Barycentric tolerance: a segment through a shared edge must not slip
  // between its two triangles because of round-off.
  if (u < -tol_ || v < -tol_ || u + v > 1 + tol_) return;
  if (t < 0 || t > 1 || t >= best_t_) return;
  best_t_ = t;
  best_n_ = n;
  hit_ = true;
}

}  // namespace xpbd_bullet::narrowphase
