// The AVX-512 lane types of the stream kernels (stream_kernel.hpp,
// tether_kernel.hpp, dihedral_kernel.hpp): 16 floats or 8 doubles per
// register. Like stream_avx2.cpp: this file alone is built with -mavx512f
// (and -ffp-contract=off, no FMA), it is called only on a CPU that reports
// AVX-512F, and the records are loaded whole and transposed in registers,
// no gather or scatter. Two or four records share a register (one per
// 256- or 128-bit part) and are transposed there. In float there is no
// Distance kernel here: the 512-bit one was no faster than AVX2 there
// (stream.cpp runs stream_avx512_ymm.cpp's or AVX2's).
#include <immintrin.h>

#include "dihedral_kernel.hpp"
#include "stream_kernel.hpp"
#include "tether_kernel.hpp"

namespace xpbd::detail {
namespace {

#if XPBD_DOUBLE
struct Avx512Lane {
  static constexpr int N = 8;
  // Two batches per group (project_stream_range): faster than one here
  // (docs/bench-distance-kernels.md, "Two batches in flight").
  static constexpr int kBatches = 2;
  using M = __mmask8;
  __m512d v;
  Avx512Lane() = default;
  explicit Avx512Lane(__m512d r) : v(r) {}
  explicit Avx512Lane(Real s) : v(_mm512_set1_pd(s)) {}
  static Avx512Lane load(const Real* p) { return Avx512Lane(_mm512_loadu_pd(p)); }
  static void store(Real* p, Avx512Lane s) { _mm512_storeu_pd(p, s.v); }
  friend Avx512Lane operator+(Avx512Lane p, Avx512Lane q) { return Avx512Lane(_mm512_add_pd(p.v, q.v)); }
  friend Avx512Lane operator-(Avx512Lane p, Avx512Lane q) { return Avx512Lane(_mm512_sub_pd(p.v, q.v)); }
  friend Avx512Lane operator*(Avx512Lane p, Avx512Lane q) { return Avx512Lane(_mm512_mul_pd(p.v, q.v)); }
  friend Avx512Lane operator/(Avx512Lane p, Avx512Lane q) { return Avx512Lane(_mm512_div_pd(p.v, q.v)); }
  friend Avx512Lane sqrt(Avx512Lane p) { return Avx512Lane(_mm512_sqrt_pd(p.v)); }
  static M gt(Avx512Lane p, Avx512Lane q) { return _mm512_cmp_pd_mask(p.v, q.v, _CMP_GT_OQ); }
  static M ge(Avx512Lane p, Avx512Lane q) { return _mm512_cmp_pd_mask(p.v, q.v, _CMP_GE_OQ); }
  static M le(Avx512Lane p, Avx512Lane q) { return _mm512_cmp_pd_mask(p.v, q.v, _CMP_LE_OQ); }
  static M eq(Avx512Lane p, Avx512Lane q) { return _mm512_cmp_pd_mask(p.v, q.v, _CMP_EQ_OQ); }
  static M both(M p, M q) { return static_cast<M>(p & q); }
  static M but_not(M p, M q) { return static_cast<M>(p & ~q); }
  static bool all(M p) { return p == 0xff; }
  static bool none(M p) { return p == 0; }
  static Avx512Lane select(M m, Avx512Lane p, Avx512Lane q) { return Avx512Lane(_mm512_mask_blend_pd(m, q.v, p.v)); }
  static Avx512Lane keep(M m, Avx512Lane p) { return Avx512Lane(_mm512_maskz_mov_pd(m, p.v)); }
  // 8 records (x, y, z, w) -> x, y, z, w of 8 lanes: records l and l + 4
  // share a register (low and high 256 bits), unpacked per 128-bit part,
  // then each component's pairs gathered by one two-source permute.
  static void load_records(const Real* const* r, Avx512Lane& x, Avx512Lane& y, Avx512Lane& z, Avx512Lane& w) {
    const __m512d r0 = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_load_pd(r[0])), _mm256_load_pd(r[4]), 1);
    const __m512d r1 = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_load_pd(r[1])), _mm256_load_pd(r[5]), 1);
    const __m512d r2 = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_load_pd(r[2])), _mm256_load_pd(r[6]), 1);
    const __m512d r3 = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_load_pd(r[3])), _mm256_load_pd(r[7]), 1);
    const __m512d t0 = _mm512_unpacklo_pd(r0, r1);  // x0 x1 | z0 z1 | x4 x5 | z4 z5
    const __m512d t1 = _mm512_unpackhi_pd(r0, r1);  // y0 y1 | w0 w1 | y4 y5 | w4 w5
    const __m512d t2 = _mm512_unpacklo_pd(r2, r3);  // x2 x3 | z2 z3 | x6 x7 | z6 z7
    const __m512d t3 = _mm512_unpackhi_pd(r2, r3);  // y2 y3 | w2 w3 | y6 y7 | w6 w7
    const __m512i lo = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0);
    const __m512i hi = _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
    x.v = _mm512_permutex2var_pd(t0, lo, t2);
    z.v = _mm512_permutex2var_pd(t0, hi, t2);
    y.v = _mm512_permutex2var_pd(t1, lo, t3);
    w.v = _mm512_permutex2var_pd(t1, hi, t3);
  }
  static void store_records(Real* const* r, Avx512Lane x, Avx512Lane y, Avx512Lane z, Avx512Lane w) {
    const __m512i lo = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0);
    const __m512i hi = _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
    const __m512d t0 = _mm512_permutex2var_pd(x.v, lo, z.v);  // x0 x1 | z0 z1 | x4 x5 | z4 z5
    const __m512d t2 = _mm512_permutex2var_pd(x.v, hi, z.v);  // x2 x3 | z2 z3 | x6 x7 | z6 z7
    const __m512d t1 = _mm512_permutex2var_pd(y.v, lo, w.v);  // y0 y1 | w0 w1 | y4 y5 | w4 w5
    const __m512d t3 = _mm512_permutex2var_pd(y.v, hi, w.v);  // y2 y3 | w2 w3 | y6 y7 | w6 w7
    const __m512d q0 = _mm512_unpacklo_pd(t0, t1);  // record 0 | 4
    const __m512d q1 = _mm512_unpackhi_pd(t0, t1);  // 1 | 5
    const __m512d q2 = _mm512_unpacklo_pd(t2, t3);  // 2 | 6
    const __m512d q3 = _mm512_unpackhi_pd(t2, t3);  // 3 | 7
    _mm256_store_pd(r[0], _mm512_castpd512_pd256(q0));
    _mm256_store_pd(r[4], _mm512_extractf64x4_pd(q0, 1));
    _mm256_store_pd(r[1], _mm512_castpd512_pd256(q1));
    _mm256_store_pd(r[5], _mm512_extractf64x4_pd(q1, 1));
    _mm256_store_pd(r[2], _mm512_castpd512_pd256(q2));
    _mm256_store_pd(r[6], _mm512_extractf64x4_pd(q2, 1));
    _mm256_store_pd(r[3], _mm512_castpd512_pd256(q3));
    _mm256_store_pd(r[7], _mm512_extractf64x4_pd(q3, 1));
  }
};
#else
struct Avx512Lane {
  static constexpr int N = 16;
  using M = __mmask16;
  __m512 v;
  Avx512Lane() = default;
  explicit Avx512Lane(__m512 r) : v(r) {}
  explicit Avx512Lane(Real s) : v(_mm512_set1_ps(s)) {}
  static Avx512Lane load(const Real* p) { return Avx512Lane(_mm512_loadu_ps(p)); }
  static void store(Real* p, Avx512Lane s) { _mm512_storeu_ps(p, s.v); }
  friend Avx512Lane operator+(Avx512Lane p, Avx512Lane q) { return Avx512Lane(_mm512_add_ps(p.v, q.v)); }
  friend Avx512Lane operator-(Avx512Lane p, Avx512Lane q) { return Avx512Lane(_mm512_sub_ps(p.v, q.v)); }
  friend Avx512Lane operator*(Avx512Lane p, Avx512Lane q) { return Avx512Lane(_mm512_mul_ps(p.v, q.v)); }
  friend Avx512Lane operator/(Avx512Lane p, Avx512Lane q) { return Avx512Lane(_mm512_div_ps(p.v, q.v)); }
  friend Avx512Lane sqrt(Avx512Lane p) { return Avx512Lane(_mm512_sqrt_ps(p.v)); }
  static M gt(Avx512Lane p, Avx512Lane q) { return _mm512_cmp_ps_mask(p.v, q.v, _CMP_GT_OQ); }
  static M ge(Avx512Lane p, Avx512Lane q) { return _mm512_cmp_ps_mask(p.v, q.v, _CMP_GE_OQ); }
  static M le(Avx512Lane p, Avx512Lane q) { return _mm512_cmp_ps_mask(p.v, q.v, _CMP_LE_OQ); }
  static M eq(Avx512Lane p, Avx512Lane q) { return _mm512_cmp_ps_mask(p.v, q.v, _CMP_EQ_OQ); }
  static M both(M p, M q) { return static_cast<M>(p & q); }
  static M but_not(M p, M q) { return static_cast<M>(p & ~q); }
  static bool all(M p) { return p == 0xffff; }
  static bool none(M p) { return p == 0; }
  static Avx512Lane select(M m, Avx512Lane p, Avx512Lane q) { return Avx512Lane(_mm512_mask_blend_ps(m, q.v, p.v)); }
  static Avx512Lane keep(M m, Avx512Lane p) { return Avx512Lane(_mm512_maskz_mov_ps(m, p.v)); }
  // 16 records (x, y, z, w) -> x, y, z, w of 16 lanes: records l, l + 4,
  // l + 8 and l + 12 share a register (one per 128-bit part), then a 4x4
  // transpose per part, as the AVX2 float lane does per half.
  static __m512 four(const Real* const* r, int l) {
    __m512 q = _mm512_castps128_ps512(_mm_load_ps(r[l]));
    q = _mm512_insertf32x4(q, _mm_load_ps(r[l + 4]), 1);
    q = _mm512_insertf32x4(q, _mm_load_ps(r[l + 8]), 2);
    return _mm512_insertf32x4(q, _mm_load_ps(r[l + 12]), 3);
  }
  static void load_records(const Real* const* r, Avx512Lane& x, Avx512Lane& y, Avx512Lane& z, Avx512Lane& w) {
    const __m512 r0 = four(r, 0), r1 = four(r, 1), r2 = four(r, 2), r3 = four(r, 3);
    const __m512 t0 = _mm512_unpacklo_ps(r0, r1);  // x0 x1 y0 y1 | x4 x5 y4 y5 | ...
    const __m512 t1 = _mm512_unpackhi_ps(r0, r1);  // z0 z1 w0 w1 | ...
    const __m512 t2 = _mm512_unpacklo_ps(r2, r3);  // x2 x3 y2 y3 | ...
    const __m512 t3 = _mm512_unpackhi_ps(r2, r3);  // z2 z3 w2 w3 | ...
    x.v = _mm512_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
    y.v = _mm512_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
    z.v = _mm512_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
    w.v = _mm512_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));
  }
  static void store_four(Real* const* r, int l, __m512 q) {
    _mm_store_ps(r[l], _mm512_castps512_ps128(q));
    _mm_store_ps(r[l + 4], _mm512_extractf32x4_ps(q, 1));
    _mm_store_ps(r[l + 8], _mm512_extractf32x4_ps(q, 2));
    _mm_store_ps(r[l + 12], _mm512_extractf32x4_ps(q, 3));
  }
  static void store_records(Real* const* r, Avx512Lane x, Avx512Lane y, Avx512Lane z, Avx512Lane w) {
    const __m512 t0 = _mm512_unpacklo_ps(x.v, y.v);  // x0 y0 x1 y1 | x4 y4 x5 y5 | ...
    const __m512 t1 = _mm512_unpackhi_ps(x.v, y.v);  // x2 y2 x3 y3 | ...
    const __m512 t2 = _mm512_unpacklo_ps(z.v, w.v);  // z0 w0 z1 w1 | ...
    const __m512 t3 = _mm512_unpackhi_ps(z.v, w.v);  // z2 w2 z3 w3 | ...
    store_four(r, 0, _mm512_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0)));  // records 0 | 4 | 8 | 12
    store_four(r, 1, _mm512_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2)));
    store_four(r, 2, _mm512_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0)));
    store_four(r, 3, _mm512_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2)));
  }
};
#endif

}  // namespace

#if XPBD_DOUBLE
void project_stream_avx512(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first) {
  project_stream_variant<Avx512Lane>(s, lo, hi, damped, first);
}
#endif

void project_tether_avx512(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first) {
  project_tether_variant<Avx512Lane>(s, lo, hi, damped, first);
}

void project_dihedral_avx512(const DihedralArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first) {
  project_dihedral_variant<Avx512Lane>(s, lo, hi, damped, first);
}

}  // namespace xpbd::detail
