#pragma once
// Internal to the bridge's particle queries (narrowphase.cpp): what its
// triangle-mesh (narrowphase_triangles.cpp) and generic convex
// (narrowphase_convex.cpp) parts share with it.
#include <btBulletCollisionCommon.h>
#include <Eigen/Geometry>

#include <limits>

#include "xpbd/types.hpp"

namespace xpbd_bullet::narrowphase {

using xpbd::Real;
using xpbd::Vec3;

inline constexpr Real kInf = std::numeric_limits<Real>::infinity();

inline Vec3 to_vec(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }
inline btVector3 to_bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }

// Length scale for round-off tolerances of a query near point p (m): features
// closer than kDegenerateRel * scale are treated as coincident.
inline Real tol_at(const Vec3& p) { return xpbd::kDegenerateRel * (Real(1) + p.cwiseAbs().maxCoeff()); }

// The closest surface point, the outward unit normal and the signed distance
// of a point p, with p == point + distance * normal.
struct Local {
  Vec3 point;
  Vec3 normal;
  Real distance;
};

// -1 for meshes (front = counter-clockwise side), the up axis for heightfields.
int front_axis(const btCollisionShape& shape);

// Keeps the nearest triangle to x within max_distance. When several triangles
// share the nearest point (an edge or a vertex), the one whose plane faces x
// most directly decides the side: on a closed mesh that is the face whose
// half-space test agrees with the true inside/outside.
class NearestTriangle : public btTriangleCallback {
 public:
  NearestTriangle(const Vec3& x, Real max_distance, int up)
      : x_(x), max_d_(max_distance), up_(up), tol_(tol_at(x)) {}

  void processTriangle(btVector3* tri, int, int) override;

  bool found() const { return found_; }

  Local result() const;

 private:
  Vec3 x_;
  Real max_d_;
  int up_;
  Real tol_;
  bool found_ = false;
  Real best_d_ = kInf;
  Real best_facing_ = 0;
  Vec3 best_q_ = Vec3::Zero();
  Vec3 best_n_ = Vec3::Zero();
  bool best_in_face_ = false;
};

// First front-face crossing of the segment a + t (b - a), t in [0, 1], with
// the triangles (Moller-Trumbore: solve a + t d = v0 + u e1 + v e2 by Cramer's
// rule). Back faces (d . n >= 0) are skipped: one-sided.
class FirstTriangleHit : public btTriangleCallback {
 public:
  FirstTriangleHit(const Vec3& a, const Vec3& b, int up)
      : a_(a), d_(b - a), up_(up), tol_(xpbd::kDegenerateRel) {}

  void processTriangle(btVector3* tri, int, int) override;

  bool hit() const { return hit_; }
  Real t() const { return best_t_; }
  const Vec3& normal() const { return best_n_; }

 private:
  Vec3 a_, d_;
  int up_;
  Real tol_;
  bool hit_ = false;
  Real best_t_ = kInf;
  Vec3 best_n_ = Vec3::Zero();
};

// Signed distance of a world point to a generic convex shape including its
// margin, by Bullet's GJK (outside) / EPA (inside). Returns false if both fail.
bool convex_signed_distance(const btConvexShape& shape, const btTransform& t, const Vec3& x, Local& out);

}  // namespace xpbd_bullet::narrowphase
