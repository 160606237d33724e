#pragma once
// Volume constraints: per tetrahedron, and the global volume enclosed by a
// closed triangle surface (balloon / pressure).
#include <Eigen/Geometry>  // cross()
#include <array>

#include "xpbd/constraints.hpp"

namespace xpbd {

// Tetrahedral volume (equality): C = V - rest_volume with the signed volume
//
//   V = (1/6) (x1 - x0).((x2 - x0) x (x3 - x0)),
//   g1 = (1/6) (x2 - x0) x (x3 - x0),  g2 = (1/6) (x3 - x0) x (x1 - x0),
//   g3 = (1/6) (x1 - x0) x (x2 - x0),  g0 = -(g1 + g2 + g3).
//
// Because V is signed, an inverted tetrahedron has C of the wrong sign and
// is pushed back through, not towards the mirrored shape. A tetrahedron with
// all four particles coincident has an all-zero gradient; the generic
// projection skips it (its denominator is not positive), so eval() never
// needs to refuse.
//
// Units: C in m^3; compliance in m^6/J (= m^5/N). For a bulk modulus K (Pa)
// the energy (K/2) (V - V0)^2 / V0 corresponds to alpha = V0/K.
struct TetVolume {
  static constexpr int kArity = 4;
  static constexpr bool kInequality = false;
  std::array<Index, 4> p{};
  Real rest_volume = 0;  // m^3, signed, != 0
  Material mat;

  static Real volume(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
    return (x1 - x0).dot((x2 - x0).cross(x3 - x0)) / Real(6);
  }

  static bool eval(const TetVolume& c, Index, const EvalContext& ctx, Real& C, Vec3* g) {
    const Vec3 x0 = ctx.x[c.p[0]];
    const Vec3 d1 = ctx.x[c.p[1]] - x0, d2 = ctx.x[c.p[2]] - x0, d3 = ctx.x[c.p[3]] - x0;
    constexpr Real sixth = Real(1) / Real(6);
    g[1] = sixth * d2.cross(d3);
    g[2] = sixth * d3.cross(d1);
    g[3] = sixth * d1.cross(d2);
    g[0] = -(g[1] + g[2] + g[3]);
    C = d1.dot(g[1]) - c.rest_volume;
    return true;
  }
};

// Global volume / pressure (equality) of a closed, consistently oriented
// (outward) triangle surface:
//
//   C = V(x) - target,  V = (1/6) sum_triangles (x_a x x_b).x_c,
//   target = pressure * V0,
//
// with grad_a V = (1/6) sum over the triangles (a, b, c) containing a of
// x_b x x_c. This is the one variable-arity type: it has no eval() and is
// projected by its own kernel, solve_global_volumes() (special_constraints.hpp),
// which the solve dispatch calls at this type's place in ConstraintTypes. Its
// triangles live flat in Model::global_volume_tris as indices into
// Model::global_volume_verts (the surface's distinct particles), and the
// gradient is accumulated in State::volume_grad (one entry per such vertex),
// so the kernel allocates nothing.
//
// Units: C in m^3; compliance in m^6/J (= m^5/N); damping in J*s/m^6.
struct GlobalVolume {
  static constexpr bool kInequality = false;
  Index tri_begin = 0, tri_end = 0;    // range in Model::global_volume_tris
  Index vert_begin = 0, vert_end = 0;  // range in Model::global_volume_verts
  Real rest_volume = 0;                // m^3, V0 > 0, enclosed in the initial positions
  Real target = 0;                     // m^3, pressure * rest_volume
  Material mat;
};

}  // namespace xpbd
