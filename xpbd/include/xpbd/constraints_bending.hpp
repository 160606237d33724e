#pragma once
// Bending constraints on a hinge: two triangles sharing an edge.
//
// Both types use the same particle layout:
//
//   p[0], p[1]  the shared (hinge) edge, e = x1 - x0
//   p[2]        the wing of triangle (p0, p1, p2)
//   p[3]        the wing of triangle (p1, p0, p3)
//
// so that two consistently oriented triangles of a mesh (counter-clockwise
// seen from the same side) give the same normal when the hinge is flat.
#include <Eigen/Geometry>  // cross()
#include <array>
#include <cmath>
#include <numbers>

#include "xpbd/constraints.hpp"

namespace xpbd {

namespace detail {
// Wraps an angle difference into (-pi, pi].
inline Real wrap_angle(Real a) {
  constexpr Real pi = std::numbers::pi_v<Real>;
  constexpr Real two_pi = 2 * std::numbers::pi_v<Real>;
  if (a > pi) a -= two_pi;
  if (a <= -pi) a += two_pi;
  return a;
}

// Hinge geometry shared by the bending constraints: the edge e = x1 - x0 and
// its length l, the unnormalized normals N1 = e x (x2 - x0), N2 = (x3 - x0) x e
// and their squared norms a1, a2. False if either triangle is degenerate
// relative to its edge lengths (|N| <= kDegenerateRel * |e| * |wing edge|),
// which includes a zero-length hinge edge.
inline bool hinge_normals(const std::array<Index, 4>& p, const Vec3* x, Vec3& e, Real& l, Vec3& n1,
                          Vec3& n2, Real& a1, Real& a2) {
  const Vec3 x0 = x[p[0]];
  e = x[p[1]] - x0;
  const Vec3 d2 = x[p[2]] - x0, d3 = x[p[3]] - x0;
  n1 = e.cross(d2);
  n2 = d3.cross(e);
  a1 = n1.squaredNorm();
  a2 = n2.squaredNorm();
  const Real l2 = e.squaredNorm();
  constexpr Real tol2 = kDegenerateRel * kDegenerateRel;
  if (!(a1 > tol2 * l2 * d2.squaredNorm()) || !(a2 > tol2 * l2 * d3.squaredNorm())) return false;
  l = std::sqrt(l2);
  return true;
}
}  // namespace detail

// Dihedral bending (equality): C = wrap(phi - rest_angle), wrapped into
// (-pi, pi], where phi in (-pi, pi] is the signed angle between the normals
//
//   N1 = e x (x2 - x0),  N2 = (x3 - x0) x e,
//   phi = atan2((N1 x N2).e/|e|, N1.N2).
//
// phi = 0 for a flat hinge; folding both wings towards +N1 makes phi < 0.
//
// Why not the seed report's C = arccos(n1.n2) - phi0: d/dd arccos(d) =
// -1/sqrt(1 - d^2) is infinite at d = 1 (flat cloth, the most common rest
// state) and at d = -1 (fully folded), and arccos loses the sign of the bend.
// atan2 of the (sine, cosine) pair is defined everywhere except for
// degenerate triangles, and the gradient below (Bridson, Marino, Fedkiw 2003,
// "Simulation of clothing with folds and wrinkles") is bounded:
//
//   g2 = -|e| N1/|N1|^2          (= -n1/h1, h1 = height of x2 over the edge)
//   g3 = -|e| N2/|N2|^2
//   g0 = -(1 - t2) g2 - (1 - t3) g3,   t_k = (x_k - x0).e/|e|^2
//   g1 = -t2 g2 - t3 g3
//
// (Each wing moves along its triangle's normal with magnitude 1/height; the
// edge vertices take the share that keeps the total force and torque zero.)
// Degenerate triangles and a zero-length hinge edge: skipped.
//
// Units: C in rad; compliance in rad^2/J (= rad/(N*m): 1/alpha is a hinge
// stiffness in N*m/rad); damping in J*s/rad^2.
struct DihedralBending {
  static constexpr int kArity = 4;
  static constexpr bool kInequality = false;
  std::array<Index, 4> p{};
  Real rest_angle = 0;  // rad, in [-pi, pi]
  Material mat;

  // Signed angle phi (rad) of the hinge at positions x, without gradient.
  // Returns false for a degenerate hinge.
  static bool angle(const std::array<Index, 4>& p, const Vec3* x, Real& phi) {
    Vec3 n1, n2, e;
    Real l, a1, a2;
    if (!detail::hinge_normals(p, x, e, l, n1, n2, a1, a2)) return false;
    phi = std::atan2(n1.cross(n2).dot(e) / l, n1.dot(n2));
    return true;
  }

  static bool eval(const DihedralBending& c, Index, const EvalContext& ctx, Real& C, Vec3* g) {
    const Vec3* x = ctx.x;
    Vec3 n1, n2, e;
    Real l, a1, a2;
    if (!detail::hinge_normals(c.p, x, e, l, n1, n2, a1, a2)) return false;
    const Real phi = std::atan2(n1.cross(n2).dot(e) / l, n1.dot(n2));
    C = detail::wrap_angle(phi - c.rest_angle);
    g[2] = (-l / a1) * n1;
    g[3] = (-l / a2) * n2;
    const Real inv_l2 = Real(1) / (l * l);
    const Real t2 = (x[c.p[2]] - x[c.p[0]]).dot(e) * inv_l2;
    const Real t3 = (x[c.p[3]] - x[c.p[0]]).dot(e) * inv_l2;
    g[0] = -(Real(1) - t2) * g[2] - (Real(1) - t3) * g[3];
    g[1] = -t2 * g[2] - t3 * g[3];
    return true;
  }

};

// Isometric bending (Bergou, Wardetzky, Harmon, Zorin, Grinspun 2006, "A
// quadratic bending model for inextensible surfaces"): for nearly isometric
// deformations the hinge's bending energy is the quadratic form
//
//   E = (k_b/2) sum_ij Q_ij x_i.x_j,   Q = 3/(A0 + A1) K K^T,
//
// with the cotangent weights K = (c03 + c04, c01 + c02, -c01 - c03,
// -c02 - c04) of the rest triangles (c01, c02: cotangents of the rest angles
// at x0 in triangles 1 and 2; c03, c04: at x1) and rest areas A0, A1. Q is
// constant, computed once by compile(). Since sum_i K_i = 0 and Q = k k^T
// with k = sqrt(3/(A0+A1)) K, we use
//
//   C = sqrt(sum_ij Q_ij x_i.x_j) = |v|,   v = sum_{i>=1} k_i (x_i - x0),
//   grad_i C = k_i v/|v|  (i >= 1),   grad_0 C = -(k1 + k2 + k3) v/|v|,
//
// so that (1/2) C^2 / alpha is exactly Bergou's energy with bending
// stiffness k_b = 1/alpha (J), and the gradient has bounded norm |k_i|.
// (The seed report's C = (1/2) sum Q x.x has a gradient that vanishes at rest,
// so its XPBD update -C/|grad C|^2 is 0/0 there.) For a small bend by an
// angle theta, C ~ sqrt(3/(A0+A1)) |e| theta. C >= 0 is minimal (0) at rest,
// where v = 0 and the direction is undefined: skipped.
//
// Like Bergou's model this assumes a flat (or near-flat) rest state: the
// cotangent weights make v vanish for every planar configuration, so the
// constraint pulls the hinge towards flat whatever its initial angle.
//
// Units: C dimensionless; compliance in 1/J (1/alpha = bending stiffness in J
// = N*m); damping in J*s.
struct IsometricBending {
  static constexpr int kArity = 4;
  static constexpr bool kInequality = false;
  std::array<Index, 4> p{};
  std::array<Real, 4> k{};  // 1/m, sqrt(3/(A0+A1)) * cotangent weights
  Material mat;

  static bool eval(const IsometricBending& c, Index, const EvalContext& ctx, Real& C, Vec3* g) {
    const Vec3 x0 = ctx.x[c.p[0]];
    Vec3 v = Vec3::Zero();
    Real scale = 0;  // magnitude of the summed terms, for the zero test
    for (int i = 1; i < 4; ++i) {
      const Vec3 d = ctx.x[c.p[i]] - x0;
      v += c.k[i] * d;
      scale += std::abs(c.k[i]) * d.norm();
    }
    Real len;
    Vec3 n;
    if (!detail::normalized(v, scale, len, n)) return false;
    C = len;
    g[0] = -(c.k[1] + c.k[2] + c.k[3]) * n;
    for (int i = 1; i < 4; ++i) g[i] = c.k[i] * n;
    return true;
  }

  // Scaled cotangent weights k of a rest hinge (layout as above). Returns
  // false if a rest triangle is degenerate (sine of one of the angles used
  // <= kDegenerateRel) so that its cotangent is undefined.
  static bool rest_weights(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                           std::array<Real, 4>& k) {
    // cot of the angle between a and b: a.b / |a x b|.
    bool ok = true;
    auto cot = [&](const Vec3& a, const Vec3& b) {
      const Real s = a.cross(b).norm();
      if (!(s > kDegenerateRel * a.norm() * b.norm())) {
        ok = false;
        return Real(0);
      }
      return a.dot(b) / s;
    };
    const Vec3 e0 = x1 - x0;
    const Real c01 = cot(e0, x2 - x0), c02 = cot(e0, x3 - x0);
    const Real c03 = cot(-e0, x2 - x1), c04 = cot(-e0, x3 - x1);
    if (!ok) return false;
    const Real area = Real(0.5) * (e0.cross(x2 - x0).norm() + e0.cross(x3 - x0).norm());
    const Real s = std::sqrt(Real(3) / area);
    k = {s * (c03 + c04), s * (c01 + c02), -s * (c01 + c03), -s * (c02 + c04)};
    return true;
  }
};

}  // namespace xpbd
