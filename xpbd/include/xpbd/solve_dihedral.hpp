#pragma once
// The dihedral bending projection written out (DihedralBending,
// constraints_bending.hpp), in place of the generic eval()-based one.
//
// The same update as project_generic, to round-off, in the same order:
//   C = wrap(phi - rest),  phi = atan2(S, D),
//   g2 = -(l/a1) N1,  g3 = -(l/a2) N2,
//   g0 = -(1 - t2) g2 - (1 - t3) g3,  g1 = -t2 g2 - t3 g3,
// with N1 = e x d2, N2 = d3 x e, a_k = |N_k|^2, e = x1 - x0, d_k = x_k - x0,
// l = |e| and t_k = d_k.e / l^2. What is written differently:
//   - S = (N1 x N2).e / l is -l e.(d2 x d3): (e x d2) x (d3 x e) =
//     -(e.(d2 x d3)) e, one cross product instead of two;
//   - sum w|g|^2 from scalars: |g2|^2 = l^2/a1, |g3|^2 = l^2/a2,
//     g2.g3 = (l^2/(a1 a2)) N1.N2, and g0, g1 are combinations of g2, g3;
//   - 1/l^2, 1/a1 and 1/a2 as three independent divisions;
//   - the four positions are read once, the masses, compliance and damping
//     factors before them, and each particle's correction is one scale of
//     the two normals (x_i += dl w_i (c_i2 g2 + c_i3 g3)).
// Degenerate hinges are skipped exactly as hinge_normals() skips them.
#include <cmath>
#include <cstddef>

#include "xpbd/constraints_bending.hpp"
#include "xpbd/solve.hpp"

namespace xpbd::detail {

template <bool kDamped, bool kXpbd>
void project_dihedral(const DihedralBending* cs, std::size_t n, Real* lambda, const SolveContext& sc) {
  const Real inv_h = Real(1) / sc.h;
  const Real inv_h2 = inv_h * inv_h;
  Vec3* const x = sc.x;
  const Vec3* const x_prev = sc.x_prev;
  const Real* const inv_mass = sc.inv_mass;
  const bool reverse = sc.reverse;
  constexpr Real tol2 = kDegenerateRel * kDegenerateRel;
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t k = visit_index(j, n, reverse);
    const DihedralBending& c = cs[k];
    const Index i0 = c.p[0], i1 = c.p[1], i2 = c.p[2], i3 = c.p[3];
    const Real w0 = inv_mass[i0], w1 = inv_mass[i1], w2 = inv_mass[i2], w3 = inv_mass[i3];
    Real at = 0, gamma = 0;
    if constexpr (kXpbd) {
      at = c.mat.compliance * inv_h2;
      if constexpr (kDamped) gamma = c.mat.compliance * c.mat.damping * inv_h;
    }

    const Vec3 x0 = x[i0];
    const Vec3 e = x[i1] - x0, d2 = x[i2] - x0, d3 = x[i3] - x0;
    const Vec3 n1 = e.cross(d2), n2 = d3.cross(e);
    const Real a1 = n1.squaredNorm(), a2 = n2.squaredNorm(), l2 = e.squaredNorm();
    const Real q2 = d2.squaredNorm(), q3 = d3.squaredNorm();
    if (!(a1 > tol2 * l2 * q2) || !(a2 > tol2 * l2 * q3)) continue;
    const Real l = std::sqrt(l2);
    const Real D = n1.dot(n2);
    const Real phi = std::atan2(-l * e.dot(d2.cross(d3)), D);
    const Real C = wrap_angle(phi - c.rest_angle);
    // Three independent divisions (they overlap in the pipeline).
    const Real inv_l2 = Real(1) / l2, inv_a1 = Real(1) / a1, inv_a2 = Real(1) / a2;
    const Real t2 = d2.dot(e) * inv_l2, t3 = d3.dot(e) * inv_l2;
    const Real f2 = -l * inv_a1, f3 = -l * inv_a2;  // g2 = f2 n1, g3 = f3 n2
    // |g2|^2 = l^2/a1, |g3|^2 = l^2/a2, g2.g3 = f2 f3 D, and g0, g1 are
    // combinations of g2 and g3: sum w|g|^2 from scalars.
    const Real s22 = l2 * inv_a1, s33 = l2 * inv_a2, s23 = f2 * f3 * D;
    const Real u2 = Real(1) - t2, u3 = Real(1) - t3;
    const Real wg = w0 * (u2 * u2 * s22 + u3 * u3 * s33 + Real(2) * u2 * u3 * s23) +
                    w1 * (t2 * t2 * s22 + t3 * t3 * s33 + Real(2) * t2 * t3 * s23) + w2 * s22 + w3 * s33;
    const Vec3 g2 = f2 * n1, g3 = f3 * n2;
    const Vec3 g0 = -u2 * g2 - u3 * g3;
    const Vec3 g1 = -t2 * g2 - t3 * g3;

    Real dl;
    if constexpr (kXpbd) {
      Real num = -C - at * lambda[k];
      Real den = wg + at;
      if constexpr (kDamped) {
        const Real gv = g0.dot(x0 - x_prev[i0]) + g1.dot(x[i1] - x_prev[i1]) + g2.dot(x[i2] - x_prev[i2]) +
                        g3.dot(x[i3] - x_prev[i3]);
        num -= gamma * gv;
        den += gamma * wg;
      }
      if (!(den > Real(0))) continue;
      dl = num / den;
    } else {
      if (!(wg > Real(0))) continue;
      dl = -c.mat.stiffness * C / wg;
    }
    lambda[k] += dl;
    x[i0] += (w0 * dl) * g0;
    x[i1] += (w1 * dl) * g1;
    x[i2] += (w2 * dl) * g2;
    x[i3] += (w3 * dl) * g3;
  }
}

}  // namespace xpbd::detail
