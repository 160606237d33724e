#pragma once
// The coloured XPBD DihedralBending kernel over a DihedralStream
// (dihedral_stream.hpp), written once for any lane type V of
// stream_kernel.hpp: ScalarLane (stream.cpp's callers, dihedral_stream.cpp)
// the AVX2 lane (stream_avx2.cpp) and the AVX-512 lane (stream_avx512.cpp).
//
// Per hinge, with e = x1 - x0, d_k = x_k - x0 (solve_dihedral.hpp's update):
//   N1 = e x d2, N2 = d3 x e, a_k = |N_k|^2, l = |e|,
//   phi = atan2(-l d2.N2, N1.N2)      (d2.N2 = e.(d2 x d3)),
//   C = wrap(phi - rest) into (-pi, pi],
//   g2 = -(l/a1) N1, g3 = -(l/a2) N2, t_k = d_k.e / l^2,
//   g0 = -(1 - t2) g2 - (1 - t3) g3, g1 = -t2 g2 - t3 g3,
//   sum w|g|^2 from scalars (|g2|^2 = l^2/a1, |g3|^2 = l^2/a2,
//   g2.g3 = (l^2/(a1 a2)) N1.N2),
//   den = sum w|g|^2 + at [+ gamma sum w|g|^2],
//   num = -C - at lambda [- gamma sum_i g_i.(x_i - p_i)],
//   dl = num / den, lambda += dl, x_i += w_i dl g_i,
// the hinge left alone where a triangle is degenerate (a_k <=
// kDegenerateRel^2 l^2 |d_k|^2, as hinge_normals() decides) or den <= 0.
// Every lane type does these operations in this order, none fuses a
// multiply and an add (-ffp-contract=off), and the angle is lane_atan2's
// (a polynomial, lane_atan2.hpp): every lane type gives the same bits.
#include <cstddef>
#include <numbers>

#include "lane_atan2.hpp"
#include "stream_kernel.hpp"

namespace xpbd::detail {

struct DihedralArgs {
  const Index* p[4] = {nullptr, nullptr, nullptr, nullptr};
  const Real* rest = nullptr;
  const Real* at = nullptr;     // compliance / h^2
  const Real* gamma = nullptr;  // compliance * damping / h (damped only)
  Real* lambda = nullptr;       // stream order
  Real* x = nullptr;            // particle records (x, y, z, 1/m)
  const Real* x_prev = nullptr; // records of the substep's start (damped only)
};

template <class V>
struct Vec3Lane {
  V x, y, z;
};

template <class V>
[[gnu::always_inline]] inline Vec3Lane<V> lane_sub(const Vec3Lane<V>& a, const Vec3Lane<V>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class V>
[[gnu::always_inline]] inline Vec3Lane<V> lane_cross(const Vec3Lane<V>& a, const Vec3Lane<V>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class V>
[[gnu::always_inline]] inline V lane_dot(const Vec3Lane<V>& a, const Vec3Lane<V>& b) {
  return (a.x * b.x + a.y * b.y) + a.z * b.z;
}
template <class V>
[[gnu::always_inline]] inline Vec3Lane<V> lane_scale(V s, const Vec3Lane<V>& a) {
  return {s * a.x, s * a.y, s * a.z};
}

// Hinges [j, j + V::N) of the stream, which share no particle. kFirst: the
// first sweep of a substep, multipliers taken as 0 and all written (as in
// stream_kernel.hpp).
template <class V, bool kDamped, bool kFirst>
[[gnu::always_inline]] inline void project_dihedral_lanes(const DihedralArgs& s, std::size_t j) {
  Real* r[4][V::N];
  for (int k = 0; k < 4; ++k)
    for (int l = 0; l < V::N; ++l)
      r[k][l] = s.x + 4 * static_cast<std::size_t>(s.p[k][j + static_cast<std::size_t>(l)]);
  Vec3Lane<V> x[4];
  V w[4];
  for (int k = 0; k < 4; ++k) V::load_records(r[k], x[k].x, x[k].y, x[k].z, w[k]);
  const V rest = V::load(s.rest + j);
  const V at = V::load(s.at + j);
  const V lam = kFirst ? V(Real(0)) : V::load(s.lambda + j);
  const V zero(Real(0)), one(Real(1));

  const Vec3Lane<V> e = lane_sub(x[1], x[0]), d2 = lane_sub(x[2], x[0]), d3 = lane_sub(x[3], x[0]);
  const Vec3Lane<V> n1 = lane_cross(e, d2), n2 = lane_cross(d3, e);
  const V a1 = lane_dot(n1, n1), a2 = lane_dot(n2, n2), l2 = lane_dot(e, e);
  const V q2 = lane_dot(d2, d2), q3 = lane_dot(d3, d3);
  const V tol2(kDegenerateRel * kDegenerateRel);
  typename V::M ok = V::both(V::gt(a1, (tol2 * l2) * q2), V::gt(a2, (tol2 * l2) * q3));
  const V l = sqrt(l2);
  const V D = lane_dot(n1, n2);
  const V phi = lane_atan2((zero - l) * lane_dot(d2, n2), D);
  constexpr Real pi = std::numbers::pi_v<Real>;
  const V pi_v(pi), two_pi(2 * pi);
  V C = phi - rest;
  C = V::select(V::gt(C, pi_v), C - two_pi, C);
  C = V::select(V::le(C, zero - pi_v), C + two_pi, C);
  // Three independent divisions (they overlap in the pipeline).
  const V inv_l2 = one / l2;
  V inv_a1, inv_a2;
  if constexpr (std::is_same_v<Real, double>) {
    const V r = one / (a1 * a2);
    inv_a1 = a2 * r, inv_a2 = a1 * r;
  } else {
    inv_a1 = one / a1, inv_a2 = one / a2;
  }
  const V t2 = lane_dot(d2, e) * inv_l2, t3 = lane_dot(d3, e) * inv_l2;
  const V f2 = (zero - l) * inv_a1, f3 = (zero - l) * inv_a2;  // g2 = f2 N1, g3 = f3 N2
  const V s22 = l2 * inv_a1, s33 = l2 * inv_a2, s23 = (f2 * f3) * D;
  const V u2 = one - t2, u3 = one - t3;
  const V two(Real(2));
  const V wg = (((w[0] * (((u2 * u2) * s22 + (u3 * u3) * s33) + ((two * u2) * u3) * s23) +
                  w[1] * (((t2 * t2) * s22 + (t3 * t3) * s33) + ((two * t2) * t3) * s23)) +
                 w[2] * s22) +
                w[3] * s33);
  Vec3Lane<V> g[4];
  g[2] = lane_scale(f2, n1);
  g[3] = lane_scale(f3, n2);
  g[0] = lane_sub(lane_scale(zero - u2, g[2]), lane_scale(u3, g[3]));
  g[1] = lane_sub(lane_scale(zero - t2, g[2]), lane_scale(t3, g[3]));

  V num = (zero - C) - at * lam;
  V den = wg + at;
  if constexpr (kDamped) {
    const Real* rp[V::N];
    V gv = zero;
    for (int k = 0; k < 4; ++k) {
      for (int l = 0; l < V::N; ++l)
        rp[l] = s.x_prev + 4 * static_cast<std::size_t>(s.p[k][j + static_cast<std::size_t>(l)]);
      Vec3Lane<V> p;
      V pw;
      V::load_records(rp, p.x, p.y, p.z, pw);
      gv = gv + lane_dot(g[k], lane_sub(x[k], p));
    }
    const V gamma = V::load(s.gamma + j);
    num = num - gamma * gv;
    den = den + gamma * wg;
  }
  ok = V::both(ok, V::gt(den, zero));
  const V dl = num / den;
  V::store(s.lambda + j, V::select(ok, lam + dl, lam));
  for (int k = 0; k < 4; ++k) {
    const V sk = w[k] * dl;
    V::store_records(r[k], V::select(ok, x[k].x + sk * g[k].x, x[k].x), V::select(ok, x[k].y + sk * g[k].y, x[k].y),
                     V::select(ok, x[k].z + sk * g[k].z, x[k].z), w[k]);
  }
}

// Hinges [lo, hi) of one colour: V::N at a time, the rest one by one.
template <class V, bool kDamped, bool kFirst>
inline void project_dihedral_range(const DihedralArgs& s, std::size_t lo, std::size_t hi) {
  std::size_t j = lo;
  for (; j + V::N <= hi; j += V::N) project_dihedral_lanes<V, kDamped, kFirst>(s, j);
  for (; j < hi; ++j) project_dihedral_lanes<ScalarLane, kDamped, kFirst>(s, j);
}

template <class V>
inline void project_dihedral_variant(const DihedralArgs& s, std::size_t lo, std::size_t hi, bool damped,
                                     bool first) {
  dispatch_variant(damped, first,
                   [&]<bool kDamped, bool kFirst>() { project_dihedral_range<V, kDamped, kFirst>(s, lo, hi); });
}

// Entry points (dihedral_stream.cpp; stream_avx2.cpp; stream_avx512.cpp).
void project_dihedral_scalar(const DihedralArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first);
void project_dihedral_avx2(const DihedralArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first);
void project_dihedral_avx512(const DihedralArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first);

}  // namespace xpbd::detail
