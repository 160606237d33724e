#pragma once
// The coloured XPBD Tether kernel over a pair stream (distance_stream.hpp,
// Model::tether_stream), written once for any lane type V, as the Distance
// kernel is (stream_kernel.hpp, whose StreamArgs and lane types it uses).
//
// Per element, with w the inverse masses, d = x_a - x_b (a the particle, b
// its anchor), L = |d| (the update of project_pair_distance in solve.hpp for
// Tether: sign -1, an inequality whose multiplier stays >= 0):
//   left alone where den <= 0, L <= kDegenerateRel * rest, or L <= rest
//   while lambda = 0 (slack);
//   num = (-rest - at lambda) + L [+ (gamma / L) d.((x_a - p_a) - (x_b - p_b))],
//   l = max(lambda + num / den, 0), dl = l - lambda, lambda = l,
//   x_a -= dl w_a / L d, x_b += dl w_b / L d.
//
// A tether's anchor is most often a pinned particle that every tether of a
// pin shares, so the colouring (compile.cpp) lets elements of one colour
// share a particle whose inverse mass is 0: such a particle never moves. So
// that no two lanes (or threads) write one record, the kernel writes a
// record only where its inverse mass is > 0: a batch whose lanes all have
// w_b = 0 (the usual case) writes no anchor, and a batch that mixes moving
// and kinematic particles on one side is projected one element at a time.
// Every lane type does the same operations in the same order without fused
// multiply-adds, so the scalar and the vector kernels give the same bits.
#include <cstddef>
#include <limits>

#include "stream_kernel.hpp"

namespace xpbd::detail {

// What a lane's projection computed: the new multiplier and positions.
template <class V>
struct TetherUpdate {
  V lam, xa, ya, za, xb, yb, zb, wa, wb;
};

template <class V, bool kDamped, bool kFirst>
[[gnu::always_inline]] inline TetherUpdate<V> tether_lanes(const StreamArgs& s, std::size_t j, Real* const* ra,
                                                           Real* const* rb) {
  TetherUpdate<V> u;
  V xa, ya, za, xb, yb, zb;
  V::load_records(ra, xa, ya, za, u.wa);
  V::load_records(rb, xb, yb, zb, u.wb);
  const V zero(Real(0));
  const V rest = V::load(s.rest + j);
  const V at = V::load(s.at + j);
  const V inv_den = V::load(s.inv_den + j);
  const V lam = kFirst ? zero : V::load(s.lambda + j);
  const V num0 = (zero - rest) - at * lam;

  const V dx = xa - xb, dy = ya - yb, dz = za - zb;
  const V q = (dx * dx + dy * dy) + dz * dz;
  const V len = sqrt(q);
  typename V::M ok = V::both(V::gt(inv_den, zero), V::gt(len, V(kDegenerateRel) * rest));
  // Slack: shorter than its length with no multiplier to give back.
  ok = V::but_not(ok, kFirst ? V::le(len, rest) : V::both(V::le(len, rest), V::eq(lam, zero)));
  V inv_len = len * (V(Real(1)) / q);
  const typename V::M normal = V::ge(q, V(std::numeric_limits<Real>::min()));
  if (!V::all(normal)) inv_len = V::select(normal, inv_len, V(Real(1)) / len);
  const V f = zero - inv_len;  // the gradient at a is f d
  V num = num0 + len;
  if constexpr (kDamped) {
    num = num - (V::load(s.gamma + j) * f) * damping_dot<V>(s, j, xa, ya, za, xb, yb, zb, dx, dy, dz);
  }
  const V sum = lam + num * inv_den;
  const V l = V::select(V::gt(zero, sum), zero, sum);
  const V dl = l - lam;
  u.lam = V::select(ok, l, lam);
  const V sa = dl * (u.wa * f), sb = dl * (u.wb * f);
  u.xa = V::select(ok, xa + sa * dx, xa), u.ya = V::select(ok, ya + sa * dy, ya);
  u.za = V::select(ok, za + sa * dz, za);
  u.xb = V::select(ok, xb - sb * dx, xb), u.yb = V::select(ok, yb - sb * dy, yb);
  u.zb = V::select(ok, zb - sb * dz, zb);
  return u;
}

// Elements [j, j + V::N) of one colour, whose particles with inverse mass > 0
// are all different. False (nothing done) if a side mixes moving and
// kinematic particles: the caller then projects them one at a time.
template <class V, bool kDamped, bool kFirst>
[[gnu::always_inline]] inline bool project_tether_lanes(const StreamArgs& s, std::size_t j) {
  Real* ra[V::N];
  Real* rb[V::N];
  for (int l = 0; l < V::N; ++l) {
    ra[l] = s.x + 4 * static_cast<std::size_t>(s.a[j + static_cast<std::size_t>(l)]);
    rb[l] = s.x + 4 * static_cast<std::size_t>(s.b[j + static_cast<std::size_t>(l)]);
  }
  const TetherUpdate<V> u = tether_lanes<V, kDamped, kFirst>(s, j, ra, rb);
  const V zero(Real(0));
  const typename V::M move_a = V::gt(u.wa, zero), move_b = V::gt(u.wb, zero);
  const bool all_a = V::all(move_a), none_a = V::none(move_a);
  const bool all_b = V::all(move_b), none_b = V::none(move_b);
  if (!(all_a || none_a) || !(all_b || none_b)) return false;
  V::store(s.lambda + j, u.lam);
  if (all_a) V::store_records(ra, u.xa, u.ya, u.za, u.wa);
  if (all_b) V::store_records(rb, u.xb, u.yb, u.zb, u.wb);
  return true;
}

// Elements [lo, hi) of one colour: V::N at a time where the batch allows it,
// the rest one by one.
template <class V, bool kDamped, bool kFirst>
inline void project_tether_range(const StreamArgs& s, std::size_t lo, std::size_t hi) {
  std::size_t j = lo;
  for (; j + V::N <= hi; j += V::N)
    if (!project_tether_lanes<V, kDamped, kFirst>(s, j))
      for (std::size_t k = j; k < j + V::N; ++k) project_tether_lanes<ScalarLane, kDamped, kFirst>(s, k);
  for (; j < hi; ++j) project_tether_lanes<ScalarLane, kDamped, kFirst>(s, j);
}

template <class V>
inline void project_tether_variant(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first) {
  dispatch_variant(damped, first,
                   [&]<bool kDamped, bool kFirst>() { project_tether_range<V, kDamped, kFirst>(s, lo, hi); });
}

// Entry points (tether_stream.cpp; stream_avx2.cpp; stream_avx512.cpp).
void project_tether_scalar(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first);
void project_tether_avx2(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first);
void project_tether_avx512(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first);

}  // namespace xpbd::detail
