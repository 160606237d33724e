#pragma once
// The coloured XPBD Distance kernel over a DistanceStream
// (distance_stream.hpp), written once for any lane type V: the scalar
// kernel (ScalarLane below, one element at a time), the AVX2 kernel
// (stream_avx2.cpp, 8 floats or 4 doubles at a time), the same width with
// AVX-512VL (stream_avx512_ymm.cpp) and the 512-bit one (stream_avx512.cpp,
// 8 doubles) instantiate it.
//
// Per element, with w the inverse masses, d = x_a - x_b, L = |d| (the
// update of project_pair_distance in solve.hpp, sign +1):
//   at = compliance / h^2, gamma = compliance * damping / h,
//   den = (w_a + w_b) + at [+ gamma (w_a + w_b)],
//   num = (rest - at lambda) - L [- (gamma / L) d.((x_a - p_a) - (x_b - p_b))],
//   dl = num / den, lambda += dl, x_a += dl w_a / L d, x_b -= dl w_b / L d,
// the element left alone where den <= 0 or L <= kDegenerateRel * rest.
// at, gamma and 1/den do not change within a step: prepare_stream computes
// them once per step (the division included; stream.cpp), the sweeps read
// them.
// Every lane type does these operations in this order, and none fuses a
// multiply and an add (the files are built with -ffp-contract=off), so
// every lane type gives the same bits.
#include <cmath>
#include <cstddef>
#include <limits>

#include "xpbd/types.hpp"

namespace xpbd::detail {

struct StreamArgs {
  const Index* a = nullptr;
  const Index* b = nullptr;
  const Real* rest = nullptr;
  const Real* at = nullptr;       // compliance / h^2
  const Real* inv_den = nullptr;  // 1 / den, 0 where den <= 0 (left alone)
  const Real* gamma = nullptr;    // compliance * damping / h (damped only)
  Real* lambda = nullptr;         // stream order
  Real* x = nullptr;              // particle records (x, y, z, 1/m)
  const Real* x_prev = nullptr;   // records of the substep's start (damped only)
};

// The lane types live in unnamed namespaces, so that every instantiation of
// the kernel is local to its file: the linker can never pick a copy
// compiled with -mavx2 or -mavx512f for a caller on a CPU without it.
namespace {

// One element at a time, in plain C++.
struct ScalarLane {
  static constexpr int N = 1;
  static constexpr int kBatches = 1;  // the Distance kernel's batches per group (project_stream_range)
  using M = bool;
  Real v;
  ScalarLane() = default;
  explicit ScalarLane(Real s) : v(s) {}
  static ScalarLane load(const Real* p) { return ScalarLane(*p); }
  static void store(Real* p, ScalarLane s) { *p = s.v; }
  friend ScalarLane operator+(ScalarLane p, ScalarLane q) { return ScalarLane(p.v + q.v); }
  friend ScalarLane operator-(ScalarLane p, ScalarLane q) { return ScalarLane(p.v - q.v); }
  friend ScalarLane operator*(ScalarLane p, ScalarLane q) { return ScalarLane(p.v * q.v); }
  friend ScalarLane operator/(ScalarLane p, ScalarLane q) { return ScalarLane(p.v / q.v); }
  friend ScalarLane sqrt(ScalarLane p) { return ScalarLane(std::sqrt(p.v)); }
  static M gt(ScalarLane p, ScalarLane q) { return p.v > q.v; }
  static M ge(ScalarLane p, ScalarLane q) { return p.v >= q.v; }
  static M le(ScalarLane p, ScalarLane q) { return p.v <= q.v; }
  static M eq(ScalarLane p, ScalarLane q) { return p.v == q.v; }
  static M both(M p, M q) { return p && q; }
  static M but_not(M p, M q) { return p && !q; }
  static bool all(M p) { return p; }
  static bool none(M p) { return !p; }
  static ScalarLane select(M m, ScalarLane p, ScalarLane q) { return m ? p : q; }
  static ScalarLane keep(M m, ScalarLane p) { return m ? p : ScalarLane(Real(0)); }
  // Records r[0..N) -> components.
  static void load_records(const Real* const* r, ScalarLane& x, ScalarLane& y, ScalarLane& z, ScalarLane& w) {
    x.v = r[0][0], y.v = r[0][1], z.v = r[0][2], w.v = r[0][3];
  }
  static void store_records(Real* const* r, ScalarLane x, ScalarLane y, ScalarLane z, ScalarLane w) {
    r[0][0] = x.v, r[0][1] = y.v, r[0][2] = z.v, r[0][3] = w.v;
  }
};

}  // namespace

// The damping term's d.((x_a - p_a) - (x_b - p_b)) of elements
// [j, j + V::N), p the records of the substep's start: the same operations
// in every pair kernel.
template <class V>
[[gnu::always_inline]] inline V damping_dot(const StreamArgs& s, std::size_t j, V xa, V ya, V za, V xb, V yb, V zb,
                                            V dx, V dy, V dz) {
  const Real* pa[V::N];
  const Real* pb[V::N];
  for (int l = 0; l < V::N; ++l) {
    pa[l] = s.x_prev + 4 * static_cast<std::size_t>(s.a[j + static_cast<std::size_t>(l)]);
    pb[l] = s.x_prev + 4 * static_cast<std::size_t>(s.b[j + static_cast<std::size_t>(l)]);
  }
  V pxa, pya, pza, pwa, pxb, pyb, pzb, pwb;
  V::load_records(pa, pxa, pya, pza, pwa);
  V::load_records(pb, pxb, pyb, pzb, pwb);
  const V vx = (xa - pxa) - (xb - pxb), vy = (ya - pya) - (yb - pyb), vz = (za - pza) - (zb - pzb);
  return (dx * vx + dy * vy) + dz * vz;
}

// The records of a batch of elements and their new values, between a
// batch's projection and their store.
template <class V>
struct PairBatch {
  Real* ra[V::N];
  Real* rb[V::N];
  V xa, ya, za, wa, xb, yb, zb, wb;
  [[gnu::always_inline]] void store() const {
    V::store_records(ra, xa, ya, za, wa);
    V::store_records(rb, xb, yb, zb, wb);
  }
};

// Projects elements [j, j + V::N) of the stream, which share no particle:
// stores their multipliers, and leaves their records' new values in r.
// kFirst: the first sweep of a substep, where every multiplier is 0: it is
// not read, and the sweep writes every element's (so nothing needs zeroing
// beforehand). 0 + dl and rest - at * 0 are what the other variant
// computes from a multiplier of +0, so both give the same bits.
template <class V, bool kDamped, bool kFirst>
[[gnu::always_inline]] inline void solve_stream_lanes(const StreamArgs& s, std::size_t j, PairBatch<V>& r) {
  for (int l = 0; l < V::N; ++l) {
    r.ra[l] = s.x + 4 * static_cast<std::size_t>(s.a[j + static_cast<std::size_t>(l)]);
    r.rb[l] = s.x + 4 * static_cast<std::size_t>(s.b[j + static_cast<std::size_t>(l)]);
  }
  V xa, ya, za, wa, xb, yb, zb, wb;
  V::load_records(r.ra, xa, ya, za, wa);
  V::load_records(r.rb, xb, yb, zb, wb);
  const V rest = V::load(s.rest + j);
  const V inv_den = V::load(s.inv_den + j);
  const V lam = kFirst ? V(Real(0)) : V::load(s.lambda + j);
  // at * +0 is +0 (at is finite: 0 where the element is left alone,
  // prepare_stream), so the first sweep need not read at.
  const V num0 = kFirst ? rest : rest - V::load(s.at + j) * lam;

  // Dependent on the positions.
  const V dx = xa - xb, dy = ya - yb, dz = za - zb;
  const V q = (dx * dx + dy * dy) + dz * dz;
  const V len = sqrt(q);
  // An element with inv_den = 0 (left alone) needs no test: at and gamma
  // are 0 there (prepare_stream), so num is finite and dl = num * 0 is
  // +-0, whose updates change no bit (below).
  const typename V::M ok = V::gt(len, V(kDegenerateRel) * rest);
  // len * (1/q) rather than 1/len (the division beside the square root),
  // except where q is subnormal and 1/q would overflow (lengths below about
  // 1e-154 m in double): only then is 1/len computed as well.
  V inv_len = len * (V(Real(1)) / q);
  const typename V::M normal = V::ge(q, V(std::numeric_limits<Real>::min()));
  if (!V::all(normal)) inv_len = V::select(normal, inv_len, V(Real(1)) / len);
  V num = num0 - len;
  if constexpr (kDamped) {
    num = num - (V::load(s.gamma + j) * inv_len) * damping_dot<V>(s, j, xa, ya, za, xb, yb, zb, dx, dy, dz);
  }
  // An element left alone (not ok) gets +0 for dl and for the two
  // factors, whatever num, inv_den and 1/L hold there (1/L is not finite
  // for L = 0): a mask each, where a blend per result took a fifth of the
  // kernel's time. lambda + 0 is lambda (never -0), and x + 0 dx is x, as
  // for the elements between two pinned particles (w = 0), bar a
  // coordinate of -0, which becomes +0.
  const V dl = num * inv_den;
  V::store(s.lambda + j, lam + V::keep(ok, dl));
  const V sa = V::keep(ok, dl * (wa * inv_len)), sb = V::keep(ok, dl * (wb * inv_len));
  r.xa = xa + sa * dx, r.ya = ya + sa * dy, r.za = za + sa * dz, r.wa = wa;
  r.xb = xb - sb * dx, r.yb = yb - sb * dy, r.zb = zb - sb * dz, r.wb = wb;
}

template <class V, bool kDamped, bool kFirst>
[[gnu::always_inline]] inline void project_stream_lanes(const StreamArgs& s, std::size_t j) {
  PairBatch<V> r;
  solve_stream_lanes<V, kDamped, kFirst>(s, j, r);
  r.store();
}

// Elements [lo, hi) of one colour: V::kBatches batches of V::N at a time,
// then V::N at a time, then the rest one by one. The batches of a group
// are all loaded and solved before any is stored (they share no particle:
// one colour), which gives the core independent chains through the square
// root and the division to overlap.
template <class V, bool kDamped, bool kFirst>
inline void project_stream_range(const StreamArgs& s, std::size_t lo, std::size_t hi) {
  constexpr int K = V::kBatches;
  constexpr std::size_t kGroup = static_cast<std::size_t>(K * V::N);
  std::size_t j = lo;
  if constexpr (K > 1) {
    for (; j + kGroup <= hi; j += kGroup) {
      PairBatch<V> b[K];
#pragma GCC unroll 4
      for (int k = 0; k < K; ++k)
        solve_stream_lanes<V, kDamped, kFirst>(s, j + static_cast<std::size_t>(k * V::N), b[k]);
#pragma GCC unroll 4
      for (int k = 0; k < K; ++k) b[k].store();
    }
  }
  for (; j + V::N <= hi; j += V::N) project_stream_lanes<V, kDamped, kFirst>(s, j);
  for (; j < hi; ++j) project_stream_lanes<ScalarLane, kDamped, kFirst>(s, j);
}

// Calls f.template operator()<kDamped, kFirst>() for the run-time flags: the
// four variants of a kernel (the stream kernels' *_variant functions).
template <class F>
inline void dispatch_variant(bool damped, bool first, F&& f) {
  if (damped) {
    if (first)
      f.template operator()<true, true>();
    else
      f.template operator()<true, false>();
  } else {
    if (first)
      f.template operator()<false, true>();
    else
      f.template operator()<false, false>();
  }
}

template <class V>
inline void project_stream_variant(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first) {
  dispatch_variant(damped, first,
                   [&]<bool kDamped, bool kFirst>() { project_stream_range<V, kDamped, kFirst>(s, lo, hi); });
}

// Entry points (stream.cpp; stream_avx2.cpp; stream_avx512.cpp).
void project_stream_scalar(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first);
void project_stream_avx2(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first);
void project_stream_avx512(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first);  // double only
void project_stream_avx512_ymm(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first);

}  // namespace xpbd::detail
