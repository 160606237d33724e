#pragma once
// A system's collision triangles in a bounding volume hierarchy, for the
// search of rigid features against them (XpbdWorld::find_triangle_contacts).
//
// FCL builds the hierarchy once (fcl::BVHModel of axis-aligned boxes, its
// default mean split, over the triangles at the first step's start). It is
// kept as a copy of FCL's tree in depth-first order and refitted here every
// step, without changing its structure, to the boxes the caller gives each
// triangle (its sweep over the step, grown by its contact band), each inner
// node's box over its two children's. The boxes are kept in single
// precision in both builds (they only filter; triangle_bvh.cpp says why
// no triangle is lost). FCL's own refit (beginUpdateModel /
// updateSubModel / endUpdateModel) fits the leaves over the vertices itself
// and took several times as long (docs/feature-contacts.md). A query walks
// the tree and returns the triangles whose box overlaps a box; the caller
// then applies its own exact tests, so the hierarchy only removes triangles
// that cannot pass them. FCL's types stay in triangle_bvh.cpp.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "xpbd/types.hpp"

namespace xpbd {
class Workers;
}

namespace xpbd_bullet::detail {

class TriangleBvh {
 public:
  TriangleBvh();
  ~TriangleBvh();
  TriangleBvh(const TriangleBvh&) = delete;
  TriangleBvh& operator=(const TriangleBvh&) = delete;

  // Builds the hierarchy on the first call, or when the triangles are not
  // the ones it was built for (x: the particles; the same vector as at the
  // last call, unchanged in size, is taken to hold the same triangles: a
  // caller that edits them in place must use a new TriangleBvh); then
  // refits it to the triangles' boxes [lo[t], hi[t]]; with a pool (workers,
  // or null), its subtrees in parallel (the same boxes).
  void update(const std::vector<std::array<xpbd::Index, 3>>& tris, const std::vector<xpbd::Vec3>& x,
              const std::vector<xpbd::Vec3>& lo, const std::vector<xpbd::Vec3>& hi,
              xpbd::Workers* workers = nullptr);
  // Appends to out, in ascending order, the triangles whose box overlaps
  // [lo, hi], and perhaps some whose box only comes within single
  // precision's rounding of it (the callers' exact tests drop those).
  void query(const xpbd::Vec3& lo, const xpbd::Vec3& hi, std::vector<int>& out) const;
  // The same, with the caller's scratch: marks holds zeros before and after
  // the call (one bit per triangle; sized here). One per thread.
  void query(const xpbd::Vec3& lo, const xpbd::Vec3& hi, std::vector<int>& out,
             std::vector<std::uint64_t>& marks) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace xpbd_bullet::detail
