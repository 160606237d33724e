#pragma once
// The triangles near one body's features, binned in a uniform grid over the
// features' box, for the search of feature-triangle contacts
// (XpbdWorld::find_triangle_contacts): each cell lists, in ascending order,
// the triangles whose box, grown by `reach`, overlaps the cell. A feature
// then tests only the triangles of the cell it is in, which hold every
// triangle whose box is within `reach` of it.
#include <utility>
#include <vector>

#include "xpbd/types.hpp"

namespace xpbd_bullet::detail {

class TriangleGrid {
 public:
  // lo, hi: the features' box. tris: the candidate triangles, ascending;
  // tri_lo, tri_hi: every triangle's box, indexed by triangle. cell: the
  // cell's side wanted (m); the side is at least reach, and the grid has at
  // most kMaxCells cells per axis.
  void build(const xpbd::Vec3& lo, const xpbd::Vec3& hi, xpbd::Real cell, xpbd::Real reach,
             const std::vector<int>& tris, const std::vector<xpbd::Vec3>& tri_lo,
             const std::vector<xpbd::Vec3>& tri_hi);
  // The triangles of the cell that holds q, a point of the features' box.
  std::pair<const int*, const int*> near(const xpbd::Vec3& q) const;

  static constexpr int kMaxCells = 16;

 private:
  // The cell of a coordinate, clamped into the grid. Monotone in v (a
  // subtraction and a product by a positive constant round monotonically,
  // and so does the truncation of a non-negative number), so a box's range
  // of cells holds the cell of every point in the box.
  int cell_of(xpbd::Real v, int axis) const {
    const xpbd::Real f = (v - origin_[axis]) * inv_;
    if (!(f >= xpbd::Real(0))) return 0;  // and NaN
    return f < xpbd::Real(n_[axis]) ? static_cast<int>(f) : n_[axis] - 1;
  }

  xpbd::Vec3 origin_ = xpbd::Vec3::Zero();
  xpbd::Real inv_ = 1;  // cells per metre
  int n_[3] = {1, 1, 1};
  std::vector<int> start_;  // cell c's triangles: tris_[start_[c] .. start_[c + 1])
  std::vector<int> tris_;
  std::vector<int> fill_;  // scratch of build()
};

}  // namespace xpbd_bullet::detail
