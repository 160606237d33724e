#pragma once
// A list of boxes stored by coordinate, for testing many of them against
// one box at a time: the rigid features' search among the triangles near
// one body (world_triangle_contacts.cpp), and the box edges' among the soft
// edges near it (world_edge_contacts.cpp). With SSE2 (every x86-64 CPU),
// two boxes per comparison in double and four in float; elsewhere one at a
// time, with the same result.
#include <vector>

#include "xpbd/types.hpp"

namespace xpbd_bullet::detail {

class BoxList {
 public:
  // Takes the boxes [lo[t], hi[t]] of the triangles `tris`, in that order.
  void assign(const std::vector<int>& tris, const std::vector<xpbd::Vec3>& lo, const std::vector<xpbd::Vec3>& hi);
  // Takes the boxes [lo[i], hi[i]], all of them, in that order.
  void assign(const std::vector<xpbd::Vec3>& lo, const std::vector<xpbd::Vec3>& hi);
  std::size_t size() const { return count_; }
  // Appends to out, in ascending order, the positions in the list given to
  // assign() of the boxes that overlap [lo, hi]: lo <= hi[t] and
  // hi >= lo[t] on every axis, as tested one at a time. A box or a query
  // with a NaN coordinate overlaps nothing.
  void overlapping(const xpbd::Vec3& lo, const xpbd::Vec3& hi, std::vector<int>& out) const;

 private:
  std::size_t count_ = 0;
  // lo x, y, z, then hi x, y, z, each padded to a whole number of lanes
  // with NaN (which overlaps nothing).
  std::vector<xpbd::Real> coords_[6];
};

}  // namespace xpbd_bullet::detail
