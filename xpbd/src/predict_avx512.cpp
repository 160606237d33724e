// The prediction pass (predict_kernel.hpp) with AVX-512: a batch of K
// particles (16 floats or 8 doubles per register) is 3 registers of their
// x, y, z in memory order; every operation but two works on those
// elementwise. The two: the inverse mass is spread from one register of K
// particles to the 3 registers' elements (a one-source permute), and the
// records (x, y, z, w) are built from two neighbouring registers by a
// two-source permute with w blended in. Built, like stream_avx512.cpp,
// with -mavx512f -ffp-contract=off, and called only on a CPU that reports
// AVX-512F. Also the contact refresh's path filter (PathArgs), which reads
// the same layout.
#include <immintrin.h>

#include "predict_kernel.hpp"

namespace xpbd::detail {
namespace {

#if XPBD_DOUBLE
using R = __m512d;
using Mask = __mmask8;
constexpr int N = 8;  // lanes
R load(const Real* p) { return _mm512_loadu_pd(p); }
void store(Real* p, R r) { _mm512_storeu_pd(p, r); }
R set1(Real s) { return _mm512_set1_pd(s); }
R add(R p, R q) { return _mm512_add_pd(p, q); }
R sub(R p, R q) { return _mm512_sub_pd(p, q); }
R mul(R p, R q) { return _mm512_mul_pd(p, q); }
Mask positive(R p) { return _mm512_cmp_pd_mask(p, _mm512_setzero_pd(), _CMP_GT_OQ); }
Mask nonzero(R p) { return _mm512_cmp_pd_mask(p, _mm512_setzero_pd(), _CMP_NEQ_UQ); }
Mask le(R p, R q) { return _mm512_cmp_pd_mask(p, q, _CMP_LE_OQ); }
R select(Mask m, R p, R q) { return _mm512_mask_blend_pd(m, q, p); }  // m ? p : q
R permute(__m512i idx, R p) { return _mm512_permutexvar_pd(idx, p); }
R permute2(R p, __m512i idx, R q) { return _mm512_permutex2var_pd(p, idx, q); }
template <class F>
__m512i indices(F f) {
  alignas(64) long long i[N];
  for (int j = 0; j < N; ++j) i[j] = f(j);
  return _mm512_load_si512(i);
}
#else
using R = __m512;
using Mask = __mmask16;
constexpr int N = 16;
R load(const Real* p) { return _mm512_loadu_ps(p); }
void store(Real* p, R r) { _mm512_storeu_ps(p, r); }
R set1(Real s) { return _mm512_set1_ps(s); }
R add(R p, R q) { return _mm512_add_ps(p, q); }
R sub(R p, R q) { return _mm512_sub_ps(p, q); }
R mul(R p, R q) { return _mm512_mul_ps(p, q); }
Mask positive(R p) { return _mm512_cmp_ps_mask(p, _mm512_setzero_ps(), _CMP_GT_OQ); }
Mask nonzero(R p) { return _mm512_cmp_ps_mask(p, _mm512_setzero_ps(), _CMP_NEQ_UQ); }
Mask le(R p, R q) { return _mm512_cmp_ps_mask(p, q, _CMP_LE_OQ); }
R select(Mask m, R p, R q) { return _mm512_mask_blend_ps(m, q, p); }
R permute(__m512i idx, R p) { return _mm512_permutexvar_ps(idx, p); }
R permute2(R p, __m512i idx, R q) { return _mm512_permutex2var_ps(p, idx, q); }
template <class F>
__m512i indices(F f) {
  alignas(64) int i[N];
  for (int j = 0; j < N; ++j) i[j] = f(j);
  return _mm512_load_si512(i);
}
#endif

// A batch: K = N particles, 3 registers of coordinates, 4 of records.
constexpr int K = N;

// The batch's tables, built once per call.
struct Tables {
  __m512i spread[3];  // element j of register k belongs to particle (k N + j) / 3
  R g[3];             // element j of register k gets g[(k N + j) % 3]
  // Record register r (4 per batch) takes its coordinates from coordinate
  // registers first[r] and first[r] + 1 (a two-source permute), and w from
  // the inverse masses.
  int first[4];
  __m512i from[4];
  __m512i w_of[4];
  Mask w_lanes;  // the lanes of a record register that hold w
};

Tables tables(const PredictArgs& a) {
  Tables t;
  for (int k = 0; k < 3; ++k) {
    t.spread[k] = indices([&](int j) { return (k * N + j) / 3; });
    alignas(64) Real g[N];
    for (int j = 0; j < N; ++j) g[j] = a.g[(k * N + j) % 3];
    t.g[k] = load(g);
  }
  constexpr int per = N / 4;  // records per register
  Mask w = 0;
  for (int j = 0; j < N; ++j)
    if (j % 4 == 3) w = static_cast<Mask>(w | (Mask(1) << j));
  t.w_lanes = w;
  for (int r = 0; r < 4; ++r) {
    const int base = 3 * per * r;  // the first coordinate of the register's first record
    t.first[r] = base / N;
    t.from[r] = indices([&](int j) {
      const int c = j % 4;
      const int flat = base + 3 * (j / 4) + (c < 3 ? c : 0);
      return flat - t.first[r] * N;  // 0..2N-1: into (first, first + 1)
    });
    t.w_of[r] = indices([&](int j) { return per * r + j / 4; });
  }
  return t;
}

// The 4 record registers of a batch from its 3 coordinate registers c and
// its inverse masses w (one register).
void put_records(Real* out, const Tables& t, const R* c, R w) {
  for (int r = 0; r < 4; ++r) {
    const R hi = t.first[r] + 1 < 3 ? c[t.first[r] + 1] : c[t.first[r]];
    const R xyz = permute2(c[t.first[r]], t.from[r], hi);
    store(out + r * N, select(t.w_lanes, permute(t.w_of[r], w), xyz));
  }
}

template <int kBefore, bool kRec, bool kRecPrev>
std::size_t run(const PredictArgs& a, std::size_t lo, std::size_t hi) {
  const Tables t = tables(a);
  const R h = set1(a.h), scale = set1(a.scale), inv_h = set1(a.inv_h), keep = set1(a.keep), blend = set1(a.blend);
  std::size_t i = lo;
  for (; i + K <= hi; i += K) {
    Real* const x = a.x + 3 * i;
    Real* const xp = a.x_prev + 3 * i;
    Real* const v = a.v + 3 * i;
    const R w = load(a.inv_mass + i);
    R c[3], old[3];
    for (int k = 0; k < 3; ++k) {
      const R wk = permute(t.spread[k], w);
      const Mask movable = positive(wk);
      const R xk = load(x + k * N);
      R vk;
      if constexpr (kBefore == 0) {
        vk = load(v + k * N);
      } else if constexpr (kBefore == 1) {
        vk = mul(sub(xk, load(xp + k * N)), scale);
      } else {
        const R measured = mul(sub(xk, load(xp + k * N)), inv_h);
        const R vo = load(v + k * N);
        vk = mul(select(movable, add(vo, mul(blend, sub(measured, vo))), measured), keep);
      }
      store(xp + k * N, xk);
      R acc = t.g[k];
      if (a.f != nullptr) acc = add(acc, mul(wk, load(a.f + 3 * i + k * N)));
      vk = select(movable, add(vk, mul(h, acc)), vk);
      store(v + k * N, vk);
      const R xn = add(xk, mul(h, vk));
      store(x + k * N, xn);
      c[k] = xn;
      old[k] = xk;
    }
    if constexpr (kRec) put_records(a.rec + 4 * i, t, c, w);
    if constexpr (kRecPrev) put_records(a.rec_prev + 4 * i, t, old, w);
  }
  return i;
}

template <int kBefore>
std::size_t run_records(const PredictArgs& a, std::size_t lo, std::size_t hi) {
  if (a.rec == nullptr) return run<kBefore, false, false>(a, lo, hi);
  if (a.rec_prev == nullptr) return run<kBefore, true, false>(a, lo, hi);
  return run<kBefore, true, true>(a, lo, hi);
}

}  // namespace

std::size_t predict_avx512(const PredictArgs& a, std::size_t lo, std::size_t hi) {
  if (hi < lo + K) return lo;
  if (a.before == 1) return run_records<1>(a, lo, hi);
  if (a.before == 2) return run_records<2>(a, lo, hi);
  return run_records<0>(a, lo, hi);
}

std::size_t off_path_avx512(const PathArgs& a, std::size_t lo, std::size_t hi, std::size_t& batch) {
  batch = lo;
  if (hi < lo + K) return lo;
  __m512i spread[3];  // as Tables::spread: element j of register k is particle (k N + j) / 3's
  for (int k = 0; k < 3; ++k) spread[k] = indices([&](int j) { return (k * N + j) / 3; });
  const R t_end = set1(a.t_end), bound2 = set1(a.bound2);
  std::size_t i = lo;
  for (; i + K <= hi; i += K) {
    const R w = load(a.inv_mass + i);
    const R dt = sub(t_end, load(a.path_t + i));
    Mask out = 0;
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = 3 * i + std::size_t(k) * N;
      const R on_path = add(load(a.path_x + at), mul(permute(spread[k], dt), load(a.path_v + at)));
      const R d = sub(load(a.x + at), on_path);
      out = static_cast<Mask>(out | (nonzero(permute(spread[k], w)) & ~le(mul(d, d), bound2)));
    }
    if (out != 0) {
      batch = i;
      return i + K;
    }
  }
  batch = i;
  return i;
}

}  // namespace xpbd::detail
