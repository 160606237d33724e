// A body's candidate triangles in a uniform grid (triangle_grid.hpp).
#include "triangle_grid.hpp"

#include <algorithm>
#include <cmath>

namespace xpbd_bullet::detail {

using xpbd::Real;
using xpbd::Vec3;

void TriangleGrid::build(const Vec3& lo, const Vec3& hi, Real cell, Real reach, const std::vector<int>& tris,
                         const std::vector<Vec3>& tri_lo, const std::vector<Vec3>& tri_hi) {
  origin_ = lo;
  const Real extent = (hi - lo).maxCoeff();
  // At most kMaxCells per axis, and no smaller than reach, so that a
  // triangle spans at most a few cells per axis even for a fast body
  // (its box grown by reach on each side); a degenerate or non-finite size
  // gives one cell.
  Real side = std::max({cell, reach, extent / Real(kMaxCells)});
  if (!(side > Real(0)) || !std::isfinite(side)) side = Real(1);
  inv_ = Real(1) / side;
  for (int a = 0; a < 3; ++a) {
    const Real f = std::ceil((hi[a] - lo[a]) * inv_);
    n_[a] = f >= Real(1) ? (f < Real(kMaxCells) ? static_cast<int>(f) : kMaxCells) : 1;
  }
  const std::size_t cells = std::size_t(n_[0]) * std::size_t(n_[1]) * std::size_t(n_[2]);
  start_.assign(cells + 1, 0);
  // Each triangle's range of cells, from its box grown by reach; counted,
  // then written, in the triangles' (ascending) order.
  auto range = [&](int t, int* a, int* b) {
    for (int k = 0; k < 3; ++k) {
      a[k] = cell_of(tri_lo[std::size_t(t)][k] - reach, k);
      b[k] = cell_of(tri_hi[std::size_t(t)][k] + reach, k);
    }
  };
  auto index = [&](int x, int y, int z) { return (std::size_t(z) * std::size_t(n_[1]) + std::size_t(y)) * std::size_t(n_[0]) + std::size_t(x); };
  int a[3], b[3];
  for (const int t : tris) {
    range(t, a, b);
    for (int z = a[2]; z <= b[2]; ++z)
      for (int y = a[1]; y <= b[1]; ++y)
        for (int x = a[0]; x <= b[0]; ++x) ++start_[index(x, y, z) + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  tris_.resize(std::size_t(start_[cells]));
  std::vector<int>& fill = fill_;
  fill.assign(start_.begin(), start_.end() - 1);
  for (const int t : tris) {
    range(t, a, b);
    for (int z = a[2]; z <= b[2]; ++z)
      for (int y = a[1]; y <= b[1]; ++y)
        for (int x = a[0]; x <= b[0]; ++x) tris_[std::size_t(fill[index(x, y, z)]++)] = t;
  }
}

std::pair<const int*, const int*> TriangleGrid::near(const Vec3& q) const {
  const std::size_t c =
      (std::size_t(cell_of(q.z(), 2)) * std::size_t(n_[1]) + std::size_t(cell_of(q.y(), 1))) * std::size_t(n_[0]) +
      std::size_t(cell_of(q.x(), 0));
  const int* base = tris_.data();
  return {base + start_[c], base + start_[c + 1]};
}

}  // namespace xpbd_bullet::detail
