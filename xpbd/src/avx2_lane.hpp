#pragma once
// The lane type of the 256-bit stream kernels (stream_kernel.hpp,
// tether_kernel.hpp, dihedral_kernel.hpp): 8 floats or 4 doubles per
// register. Included by the files that are built for one instruction set
// each, in an unnamed namespace, so that each gets its own copy:
//   - stream_avx2.cpp (-mavx2): comparisons give vector masks, and a
//     select is a blend;
//   - stream_avx512_ymm.cpp (-mavx512f -mavx512vl): the same registers'
//     width with AVX-512VL, where comparisons give mask registers, and the
//     compiler has 32 vector registers instead of 16 (the Distance kernel
//     spilled to the stack with 16).
// Both do the same floating-point operations (-ffp-contract=off, no FMA),
// so both give the scalar kernel's bits. Particle records are loaded
// whole (one 16- or 32-byte load per particle) and transposed in
// registers into x, y, z, w vectors: no gather or scatter instruction,
// which on the measured AMD core were slower than scalar code.
#include <immintrin.h>

#include "xpbd/types.hpp"

namespace xpbd::detail {
namespace {

#if XPBD_DOUBLE
struct Avx2Lane {
  static constexpr int N = 4;
  // One batch per group: two were slower in double, with AVX2 and with
  // AVX-512VL alike (docs/bench-distance-kernels.md, "Two batches in flight").
  static constexpr int kBatches = 1;
#ifdef __AVX512VL__
  using M = __mmask8;
#else
  using M = __m256d;
#endif
  __m256d v;
  Avx2Lane() = default;
  explicit Avx2Lane(__m256d r) : v(r) {}
  explicit Avx2Lane(Real s) : v(_mm256_set1_pd(s)) {}
  static Avx2Lane load(const Real* p) { return Avx2Lane(_mm256_loadu_pd(p)); }
  static void store(Real* p, Avx2Lane s) { _mm256_storeu_pd(p, s.v); }
  friend Avx2Lane operator+(Avx2Lane p, Avx2Lane q) { return Avx2Lane(_mm256_add_pd(p.v, q.v)); }
  friend Avx2Lane operator-(Avx2Lane p, Avx2Lane q) { return Avx2Lane(_mm256_sub_pd(p.v, q.v)); }
  friend Avx2Lane operator*(Avx2Lane p, Avx2Lane q) { return Avx2Lane(_mm256_mul_pd(p.v, q.v)); }
  friend Avx2Lane operator/(Avx2Lane p, Avx2Lane q) { return Avx2Lane(_mm256_div_pd(p.v, q.v)); }
  friend Avx2Lane sqrt(Avx2Lane p) { return Avx2Lane(_mm256_sqrt_pd(p.v)); }
#ifdef __AVX512VL__
  static M gt(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_pd_mask(p.v, q.v, _CMP_GT_OQ); }
  static M ge(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_pd_mask(p.v, q.v, _CMP_GE_OQ); }
  static M le(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_pd_mask(p.v, q.v, _CMP_LE_OQ); }
  static M eq(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_pd_mask(p.v, q.v, _CMP_EQ_OQ); }
  static M both(M p, M q) { return static_cast<M>(p & q); }
  static M but_not(M p, M q) { return static_cast<M>(p & ~q); }
  static bool all(M p) { return (p & 0xf) == 0xf; }
  static bool none(M p) { return (p & 0xf) == 0; }
  static Avx2Lane select(M m, Avx2Lane p, Avx2Lane q) { return Avx2Lane(_mm256_mask_blend_pd(m, q.v, p.v)); }
  static Avx2Lane keep(M m, Avx2Lane p) { return Avx2Lane(_mm256_maskz_mov_pd(m, p.v)); }
#else
  static M gt(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_pd(p.v, q.v, _CMP_GT_OQ); }
  static M ge(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_pd(p.v, q.v, _CMP_GE_OQ); }
  static M le(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_pd(p.v, q.v, _CMP_LE_OQ); }
  static M eq(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_pd(p.v, q.v, _CMP_EQ_OQ); }
  static M both(M p, M q) { return _mm256_and_pd(p, q); }
  static M but_not(M p, M q) { return _mm256_andnot_pd(q, p); }
  static bool all(M p) { return _mm256_movemask_pd(p) == 0xf; }
  static bool none(M p) { return _mm256_movemask_pd(p) == 0; }
  static Avx2Lane select(M m, Avx2Lane p, Avx2Lane q) { return Avx2Lane(_mm256_blendv_pd(q.v, p.v, m)); }
  static Avx2Lane keep(M m, Avx2Lane p) { return Avx2Lane(_mm256_and_pd(m, p.v)); }
#endif
  // 4 records (x, y, z, w) -> x, y, z, w of 4 lanes.
  static void load_records(const Real* const* r, Avx2Lane& x, Avx2Lane& y, Avx2Lane& z, Avx2Lane& w) {
    const __m256d r0 = _mm256_load_pd(r[0]), r1 = _mm256_load_pd(r[1]);
    const __m256d r2 = _mm256_load_pd(r[2]), r3 = _mm256_load_pd(r[3]);
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1);  // x0 x1 | z0 z1
    const __m256d t1 = _mm256_unpackhi_pd(r0, r1);  // y0 y1 | w0 w1
    const __m256d t2 = _mm256_unpacklo_pd(r2, r3);  // x2 x3 | z2 z3
    const __m256d t3 = _mm256_unpackhi_pd(r2, r3);  // y2 y3 | w2 w3
    x.v = _mm256_permute2f128_pd(t0, t2, 0x20);
    z.v = _mm256_permute2f128_pd(t0, t2, 0x31);
    y.v = _mm256_permute2f128_pd(t1, t3, 0x20);
    w.v = _mm256_permute2f128_pd(t1, t3, 0x31);
  }
  static void store_records(Real* const* r, Avx2Lane x, Avx2Lane y, Avx2Lane z, Avx2Lane w) {
    const __m256d t0 = _mm256_permute2f128_pd(x.v, z.v, 0x20);  // x0 x1 | z0 z1
    const __m256d t2 = _mm256_permute2f128_pd(x.v, z.v, 0x31);  // x2 x3 | z2 z3
    const __m256d t1 = _mm256_permute2f128_pd(y.v, w.v, 0x20);  // y0 y1 | w0 w1
    const __m256d t3 = _mm256_permute2f128_pd(y.v, w.v, 0x31);  // y2 y3 | w2 w3
    _mm256_store_pd(r[0], _mm256_unpacklo_pd(t0, t1));
    _mm256_store_pd(r[1], _mm256_unpackhi_pd(t0, t1));
    _mm256_store_pd(r[2], _mm256_unpacklo_pd(t2, t3));
    _mm256_store_pd(r[3], _mm256_unpackhi_pd(t2, t3));
  }
};
#else
struct Avx2Lane {
  static constexpr int N = 8;
  // Two batches per group (project_stream_range): faster in float, with
  // AVX2 and with AVX-512VL (docs/bench-distance-kernels.md).
  static constexpr int kBatches = 2;
#ifdef __AVX512VL__
  using M = __mmask8;
#else
  using M = __m256;
#endif
  __m256 v;
  Avx2Lane() = default;
  explicit Avx2Lane(__m256 r) : v(r) {}
  explicit Avx2Lane(Real s) : v(_mm256_set1_ps(s)) {}
  static Avx2Lane load(const Real* p) { return Avx2Lane(_mm256_loadu_ps(p)); }
  static void store(Real* p, Avx2Lane s) { _mm256_storeu_ps(p, s.v); }
  friend Avx2Lane operator+(Avx2Lane p, Avx2Lane q) { return Avx2Lane(_mm256_add_ps(p.v, q.v)); }
  friend Avx2Lane operator-(Avx2Lane p, Avx2Lane q) { return Avx2Lane(_mm256_sub_ps(p.v, q.v)); }
  friend Avx2Lane operator*(Avx2Lane p, Avx2Lane q) { return Avx2Lane(_mm256_mul_ps(p.v, q.v)); }
  friend Avx2Lane operator/(Avx2Lane p, Avx2Lane q) { return Avx2Lane(_mm256_div_ps(p.v, q.v)); }
  friend Avx2Lane sqrt(Avx2Lane p) { return Avx2Lane(_mm256_sqrt_ps(p.v)); }
#ifdef __AVX512VL__
  static M gt(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_ps_mask(p.v, q.v, _CMP_GT_OQ); }
  static M ge(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_ps_mask(p.v, q.v, _CMP_GE_OQ); }
  static M le(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_ps_mask(p.v, q.v, _CMP_LE_OQ); }
  static M eq(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_ps_mask(p.v, q.v, _CMP_EQ_OQ); }
  static M both(M p, M q) { return static_cast<M>(p & q); }
  static M but_not(M p, M q) { return static_cast<M>(p & ~q); }
  static bool all(M p) { return p == 0xff; }
  static bool none(M p) { return p == 0; }
  static Avx2Lane select(M m, Avx2Lane p, Avx2Lane q) { return Avx2Lane(_mm256_mask_blend_ps(m, q.v, p.v)); }
  static Avx2Lane keep(M m, Avx2Lane p) { return Avx2Lane(_mm256_maskz_mov_ps(m, p.v)); }
#else
  static M gt(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_ps(p.v, q.v, _CMP_GT_OQ); }
  static M ge(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_ps(p.v, q.v, _CMP_GE_OQ); }
  static M le(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_ps(p.v, q.v, _CMP_LE_OQ); }
  static M eq(Avx2Lane p, Avx2Lane q) { return _mm256_cmp_ps(p.v, q.v, _CMP_EQ_OQ); }
  static M both(M p, M q) { return _mm256_and_ps(p, q); }
  static M but_not(M p, M q) { return _mm256_andnot_ps(q, p); }
  static bool all(M p) { return _mm256_movemask_ps(p) == 0xff; }
  static bool none(M p) { return _mm256_movemask_ps(p) == 0; }
  static Avx2Lane select(M m, Avx2Lane p, Avx2Lane q) { return Avx2Lane(_mm256_blendv_ps(q.v, p.v, m)); }
  static Avx2Lane keep(M m, Avx2Lane p) { return Avx2Lane(_mm256_and_ps(m, p.v)); }
#endif
  // 8 records (x, y, z, w) -> x, y, z, w of 8 lanes: records l and l + 4
  // share a register (low and high half), then a 4x4 transpose per half.
  static void load_records(const Real* const* r, Avx2Lane& x, Avx2Lane& y, Avx2Lane& z, Avx2Lane& w) {
    const __m256 r0 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(r[0])), _mm_load_ps(r[4]), 1);
    const __m256 r1 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(r[1])), _mm_load_ps(r[5]), 1);
    const __m256 r2 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(r[2])), _mm_load_ps(r[6]), 1);
    const __m256 r3 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(r[3])), _mm_load_ps(r[7]), 1);
    const __m256 t0 = _mm256_unpacklo_ps(r0, r1);  // x0 x1 y0 y1 | x4 x5 y4 y5
    const __m256 t1 = _mm256_unpackhi_ps(r0, r1);  // z0 z1 w0 w1 | ...
    const __m256 t2 = _mm256_unpacklo_ps(r2, r3);  // x2 x3 y2 y3 | ...
    const __m256 t3 = _mm256_unpackhi_ps(r2, r3);  // z2 z3 w2 w3 | ...
    x.v = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
    y.v = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
    z.v = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
    w.v = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));
  }
  static void store_records(Real* const* r, Avx2Lane x, Avx2Lane y, Avx2Lane z, Avx2Lane w) {
    const __m256 t0 = _mm256_unpacklo_ps(x.v, y.v);  // x0 y0 x1 y1 | x4 y4 x5 y5
    const __m256 t1 = _mm256_unpackhi_ps(x.v, y.v);  // x2 y2 x3 y3 | ...
    const __m256 t2 = _mm256_unpacklo_ps(z.v, w.v);  // z0 w0 z1 w1 | ...
    const __m256 t3 = _mm256_unpackhi_ps(z.v, w.v);  // z2 w2 z3 w3 | ...
    const __m256 q0 = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));  // record 0 | 4
    const __m256 q1 = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));  // 1 | 5
    const __m256 q2 = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));  // 2 | 6
    const __m256 q3 = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));  // 3 | 7
    _mm_store_ps(r[0], _mm256_castps256_ps128(q0));
    _mm_store_ps(r[4], _mm256_extractf128_ps(q0, 1));
    _mm_store_ps(r[1], _mm256_castps256_ps128(q1));
    _mm_store_ps(r[5], _mm256_extractf128_ps(q1, 1));
    _mm_store_ps(r[2], _mm256_castps256_ps128(q2));
    _mm_store_ps(r[6], _mm256_extractf128_ps(q2, 1));
    _mm_store_ps(r[3], _mm256_castps256_ps128(q3));
    _mm_store_ps(r[7], _mm256_extractf128_ps(q3, 1));
  }
};
#endif

}  // namespace
}  // namespace xpbd::detail
