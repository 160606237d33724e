#pragma once
// Shared pieces of the narrowphase tests: rigid poses built from an axis-angle
// rotation (the test's own frame math is Eigen, independent of Bullet's), and
// reference signed distance functions written differently from the
// production closed forms (the production code branches per Voronoi region;
// these use compact max/min formulas over features).
#include <btBulletCollisionCommon.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "xpbd/types.hpp"
#include "xpbd_bullet/narrowphase.hpp"

namespace np_test {

using xpbd::Real;
using xpbd::Vec3;
using D3 = Eigen::Vector3d;  // references are evaluated in double in every build

// Round-off scale of the scalar the code under test uses.
inline constexpr double kEps = std::numeric_limits<Real>::epsilon();
// Tolerance of a closed-form answer: O(10) operations on coordinates of up to
// a few metres (poses included) lose a few eps * |x|; 512 eps (1.1e-13 m in
// double, 6e-5 m in float) leaves a margin of ~10.
inline constexpr double kT = 512 * kEps;

// A rigid pose: world = R local + t.
struct Pose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  D3 t = D3::Zero();
  D3 to_local(const D3& x) const { return R.transpose() * (x - t); }
  D3 to_world(const D3& p) const { return R * p + t; }
};

inline Pose make_pose(const D3& axis, double angle, const D3& t) {
  return {Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(), t};
}

inline btTransform to_bt(const Pose& p) {
  const Eigen::Matrix3d& R = p.R;
  btMatrix3x3 basis(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2));
  return btTransform(basis, btVector3(p.t.x(), p.t.y(), p.t.z()));
}

inline D3 d3(const Vec3& v) { return v.cast<double>(); }
inline Vec3 vec(const D3& v) { return v.cast<Real>(); }

// A collision object owning nothing: shape and pose set by the test.
inline std::unique_ptr<btCollisionObject> make_object(btCollisionShape* shape, const Pose& pose) {
  auto o = std::make_unique<btCollisionObject>();
  o->setCollisionShape(shape);
  o->setWorldTransform(to_bt(pose));
  return o;
}

// ---- reference signed distances in the shape's local frame ----
inline double ref_sphere(double radius, const D3& p) { return p.norm() - radius; }

// Box: |max(q, 0)| + min(max_i q_i, 0) with q = |p| - h.
inline double ref_box(const D3& h, const D3& p) {
  const D3 q = p.cwiseAbs() - h;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

// Capsule: the distance to the core segment as the minimum over its features
// (the two end points, and the open segment where p projects onto it), minus R.
inline double ref_capsule(int up, double radius, double half_height, const D3& p) {
  const D3 e = D3::Unit(up);
  double d = std::min((p - half_height * e).norm(), (p + half_height * e).norm());
  if (std::abs(p[up]) <= half_height) d = std::min(d, (p - p[up] * e).norm());
  return d - radius;
}

// Cylinder: the 2-D box formula in (radial distance, |axial|).
inline double ref_cylinder(int up, double radius, double half_height, const D3& p) {
  D3 radial = p;
  radial[up] = 0;
  const Eigen::Vector2d q(radial.norm() - radius, std::abs(p[up]) - half_height);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

// Central-difference gradient of a reference SDF with steps h = 1e-6 m and
// 2h: truncation error ~ h^2 * (third derivative), round-off ~ 1e-16 / h =
// 1e-10. The normal is only compared where it is well defined and the
// difference quotient is trustworthy: |gradient| = 1 within 1e-6 (not near
// the medial axis, where the nearest feature is not unique) and the h and 2h
// estimates agree within 1e-8 (not within h of a Voronoi region boundary,
// where the SDF is only C1 and the quotient's error is ~h / distance).
template <class F>
bool ref_normal(F&& sdf, const D3& p, D3& n) {
  const double h = 1e-6;
  D3 n2;
  for (int i = 0; i < 3; ++i) {
    n[i] = (sdf(p + h * D3::Unit(i)) - sdf(p - h * D3::Unit(i))) / (2 * h);
    n2[i] = (sdf(p + 2 * h * D3::Unit(i)) - sdf(p - 2 * h * D3::Unit(i))) / (4 * h);
  }
  const bool unique = std::abs(n.norm() - 1) < 1e-6 && (n - n2).norm() < 1e-8;
  n.normalize();
  return unique;
}

// Cube mesh (12 triangles, counter-clockwise seen from outside) of half
// extents h; the caller keeps the btTriangleMesh alive.
inline void add_box_triangles(btTriangleMesh& mesh, const D3& h) {
  auto v = [&](int i) { return btVector3(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z()); };
  // Each face as a quad a, b, c, d ordered counter-clockwise seen from outside.
  const int quads[6][4] = {{1, 3, 7, 5}, {0, 4, 6, 2}, {2, 6, 7, 3}, {0, 1, 5, 4}, {4, 5, 7, 6}, {0, 2, 3, 1}};
  for (const auto& q : quads) {
    mesh.addTriangle(v(q[0]), v(q[1]), v(q[2]));
    mesh.addTriangle(v(q[0]), v(q[2]), v(q[3]));
  }
}

}  // namespace np_test
