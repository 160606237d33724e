#pragma once
// Contact-like inequality constraints: point-triangle penetration and the
// long-range attachment (tether).
#include <Eigen/Geometry>  // cross()
#include <array>
#include <cmath>

#include "xpbd/constraints.hpp"

namespace xpbd {

// Point-triangle penetration (inequality): point q = p[0] against the plane
// of triangle (p1, p2, p3) = (p[1], p[2], p[3]),
//
//   C = s (q - x1).n - thickness >= 0,   n = N/|N|,  N = (x2 - x1) x (x3 - x1),
//
// where s = +1 or -1 is the side q was on at the start of the step
// (EvalContext::penetration_side, recorded by step()). A point that crossed
// the triangle during the step is therefore pushed back to the side it came
// from, not further through. The element constrains q against the whole
// plane of the triangle: collision detection decides which (point, triangle)
// pairs are in contact.
//
// Gradient (own closed form; with d = q - x1, A = |N|, e1 = x2 - x1,
// e2 = x3 - x1 and u = (d - (d.n) n)/A the in-plane part of d over A, using
// dn/dN = (I - n n^T)/A and dN = de1 x e2 + e1 x de2):
//
//   g_q  = s n
//   g_p2 = s e2 x u
//   g_p3 = s u x e1
//   g_p1 = -(g_q + g_p2 + g_p3)      (translation invariance)
//
// Zero-area triangle (|N| <= kDegenerateRel |e1||e2|): normal undefined,
// skipped.
//
// Units: C in m; compliance in m/N; damping in N*s/m.
struct Penetration {
  static constexpr int kArity = 4;
  static constexpr bool kInequality = true;
  std::array<Index, 4> p{};  // p[0] = point q; p[1], p[2], p[3] = triangle
  Real thickness = 0;        // m, >= 0, distance kept from the plane
  Material mat;

  // Side (+1 or -1) of q relative to the triangle at positions x. A point
  // exactly in the plane, or a degenerate triangle, counts as +1 (the side
  // the normal points to).
  static Real side(const Penetration& c, const Vec3* x) {
    const Vec3 x1 = x[c.p[1]];
    const Vec3 n = (x[c.p[2]] - x1).cross(x[c.p[3]] - x1);
    return n.dot(x[c.p[0]] - x1) >= Real(0) ? Real(1) : Real(-1);
  }

  static bool eval(const Penetration& c, Index k, const EvalContext& ctx, Real& C, Vec3* g) {
    const Vec3* x = ctx.x;
    return point_triangle(x[c.p[0]], x[c.p[1]], x[c.p[2]], x[c.p[3]], ctx.penetration_side[k],
                          c.thickness, C, g);
  }

  // The math of eval() for explicit positions (shared with rigid-vertex
  // contacts against cloth triangles, rigid.hpp): C and the gradients
  // g[0] (point), g[1..3] (triangle) for point q and triangle (x1, x2, x3).
  static bool point_triangle(const Vec3& q, const Vec3& x1, const Vec3& x2, const Vec3& x3, Real s,
                             Real thickness, Real& C, Vec3* g) {
    const Vec3 e1 = x2 - x1, e2 = x3 - x1;
    const Vec3 nn = e1.cross(e2);
    const Real area2 = nn.norm();  // twice the triangle area
    if (!(area2 > kDegenerateRel * e1.norm() * e2.norm())) return false;
    const Vec3 n = nn / area2;
    const Vec3 d = q - x1;
    const Real dn = d.dot(n);
    C = s * dn - thickness;
    const Vec3 u = (d - dn * n) / area2;
    g[0] = s * n;
    g[2] = s * e2.cross(u);
    g[3] = s * u.cross(e1);
    g[1] = -(g[0] + g[2] + g[3]);
    return true;
  }
};

// Long-range attachment / tether (inequality): particle p[0] may not move
// further than `length` from anchor particle p[1] (usually pinned or
// kinematic):
//
//   C = length - |x0 - x1| >= 0,   g0 = -(x0 - x1)/|x0 - x1|,  g1 = -g0.
//
// `length` is the rest Euclidean distance or a geodesic length along the
// cloth, which is never shorter. Coincident particles: skipped (C = length
// > 0 there anyway, so the constraint would be inactive).
//
// Units: C in m; compliance in m/N; damping in N*s/m.
struct Tether {
  static constexpr int kArity = 2;
  static constexpr bool kInequality = true;
  std::array<Index, 2> p{};  // p[0] = particle, p[1] = anchor
  Real length = 0;           // m, > 0
  Material mat;

  static bool eval(const Tether& c, Index, const EvalContext& ctx, Real& C, Vec3* g) {
    Real len;
    Vec3 n;
    if (!detail::normalized(ctx.x[c.p[0]] - ctx.x[c.p[1]], c.length, len, n)) return false;
    C = c.length - len;
    g[0] = -n;
    g[1] = n;
    return true;
  }
};

}  // namespace xpbd
