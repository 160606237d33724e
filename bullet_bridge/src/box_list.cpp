// A list of boxes by coordinate (box_list.hpp).
#include "box_list.hpp"

#include <limits>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace xpbd_bullet::detail {

using xpbd::Real;
using xpbd::Vec3;

namespace {
constexpr std::size_t kLanes = 4;  // the padding: a whole number of lanes in either precision

// Box i of the list is [lo[at(i)], hi[at(i)]], i < count.
template <class At>
void fill(std::vector<Real> (&coords)[6], std::size_t count, const std::vector<Vec3>& lo, const std::vector<Vec3>& hi,
          At at) {
  const std::size_t padded = (count + kLanes - 1) / kLanes * kLanes;
  for (auto& c : coords) c.resize(padded);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3& l = lo[at(i)];
    const Vec3& h = hi[at(i)];
    for (int k = 0; k < 3; ++k) {
      coords[k][i] = l[k];
      coords[3 + k][i] = h[k];
    }
  }
  for (auto& c : coords)
    for (std::size_t i = count; i < padded; ++i) c[i] = std::numeric_limits<Real>::quiet_NaN();
}

}  // namespace

void BoxList::assign(const std::vector<int>& tris, const std::vector<Vec3>& lo, const std::vector<Vec3>& hi) {
  count_ = tris.size();
  fill(coords_, count_, lo, hi, [&tris](std::size_t i) { return std::size_t(tris[i]); });
}

void BoxList::assign(const std::vector<Vec3>& lo, const std::vector<Vec3>& hi) {
  count_ = lo.size();
  fill(coords_, count_, lo, hi, [](std::size_t i) { return i; });
}

void BoxList::overlapping(const Vec3& lo, const Vec3& hi, std::vector<int>& out) const {
  const Real* const lx = coords_[0].data();
  const Real* const ly = coords_[1].data();
  const Real* const lz = coords_[2].data();
  const Real* const hx = coords_[3].data();
  const Real* const hy = coords_[4].data();
  const Real* const hz = coords_[5].data();
  const std::size_t padded = coords_[0].size();
  std::size_t i = 0;
#ifdef __SSE2__
  // The ordered comparisons (_CMP_LE_OQ's SSE2 forms) are false for NaN,
  // like the scalar ones below.
  if constexpr (sizeof(Real) == sizeof(double)) {
    const __m128d qlx = _mm_set1_pd(double(lo.x())), qly = _mm_set1_pd(double(lo.y())),
                  qlz = _mm_set1_pd(double(lo.z())), qhx = _mm_set1_pd(double(hi.x())),
                  qhy = _mm_set1_pd(double(hi.y())), qhz = _mm_set1_pd(double(hi.z()));
    for (; i + 2 <= padded; i += 2) {
      const auto at = [i](const Real* p) { return _mm_loadu_pd(reinterpret_cast<const double*>(p + i)); };
      __m128d m = _mm_cmple_pd(at(lx), qhx);
      m = _mm_and_pd(m, _mm_cmple_pd(at(ly), qhy));
      m = _mm_and_pd(m, _mm_cmple_pd(at(lz), qhz));
      m = _mm_and_pd(m, _mm_cmpge_pd(at(hx), qlx));
      m = _mm_and_pd(m, _mm_cmpge_pd(at(hy), qly));
      m = _mm_and_pd(m, _mm_cmpge_pd(at(hz), qlz));
      const int bits = _mm_movemask_pd(m);
      if (bits & 1) out.push_back(int(i));
      if (bits & 2) out.push_back(int(i) + 1);
    }
  } else {
    const __m128 qlx = _mm_set1_ps(float(lo.x())), qly = _mm_set1_ps(float(lo.y())), qlz = _mm_set1_ps(float(lo.z())),
                 qhx = _mm_set1_ps(float(hi.x())), qhy = _mm_set1_ps(float(hi.y())), qhz = _mm_set1_ps(float(hi.z()));
    for (; i + 4 <= padded; i += 4) {
      const auto at = [i](const Real* p) { return _mm_loadu_ps(reinterpret_cast<const float*>(p + i)); };
      __m128 m = _mm_cmple_ps(at(lx), qhx);
      m = _mm_and_ps(m, _mm_cmple_ps(at(ly), qhy));
      m = _mm_and_ps(m, _mm_cmple_ps(at(lz), qhz));
      m = _mm_and_ps(m, _mm_cmpge_ps(at(hx), qlx));
      m = _mm_and_ps(m, _mm_cmpge_ps(at(hy), qly));
      m = _mm_and_ps(m, _mm_cmpge_ps(at(hz), qlz));
      for (int bits = _mm_movemask_ps(m); bits != 0; bits &= bits - 1)
        out.push_back(int(i) + __builtin_ctz(unsigned(bits)));
    }
  }
#endif
  for (; i < padded; ++i)
    if (lx[i] <= hi.x() && ly[i] <= hi.y() && lz[i] <= hi.z() && hx[i] >= lo.x() && hy[i] >= lo.y() && hz[i] >= lo.z())
      out.push_back(int(i));
}

}  // namespace xpbd_bullet::detail
