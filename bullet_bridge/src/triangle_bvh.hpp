#pragma once
// A system's collision triangles in an FCL bounding volume hierarchy, for the
// search of rigid features against them (XpbdWorld::find_triangle_contacts).
//
// FCL builds the hierarchy once (fcl::BVHModel of axis-aligned boxes, its
// default split) and refits it every step without changing its structure
// (beginUpdateModel / updateSubModel / endUpdateModel with refit): each
// leaf's box is fitted over the triangle's corners at the step's start and
// at its end without contacts (x and x + dt v), so it holds the triangle's
// straight sweep over the step. A query walks the tree and returns the
// triangles whose swept box overlaps a box; the caller then applies its own
// exact tests, so the hierarchy only removes triangles that cannot pass them.
// FCL's types stay in triangle_bvh.cpp.
#include <array>
#include <memory>
#include <vector>

#include "xpbd/types.hpp"

namespace xpbd_bullet::detail {

class TriangleBvh {
 public:
  TriangleBvh();
  ~TriangleBvh();
  TriangleBvh(const TriangleBvh&) = delete;
  TriangleBvh& operator=(const TriangleBvh&) = delete;

  // Builds the hierarchy on the first call, or when the triangles are not
  // the ones it was built for; refits it otherwise. x: the particles at the
  // step's start, v their velocities.
  void update(const std::vector<std::array<xpbd::Index, 3>>& tris, const std::vector<xpbd::Vec3>& x,
              const std::vector<xpbd::Vec3>& v, xpbd::Real dt);
  // Appends to out, in ascending order, the triangles whose swept box
  // overlaps [lo, hi].
  void query(const xpbd::Vec3& lo, const xpbd::Vec3& hi, std::vector<int>& out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace xpbd_bullet::detail
