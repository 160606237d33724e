#pragma once
// Shortest paths along a mesh's edges (builders.cpp's geodesic tethers).
#include <array>
#include <vector>

#include "xpbd/types.hpp"

namespace xpbd::detail {

// For every particle, the nearest of `anchors` along the edges (weighted by
// their lengths in x) and that distance (m): one Dijkstra search from all
// anchors at once, on (distance, anchor's position in `anchors`) in
// lexicographic order, so equal distances go to the anchor listed first.
// The distance is the smallest over anchors of what edge_path_distances
// gives from each (rounding is monotone, so the smallest float sum along
// the edges is the same). One exception to "listed first": where two
// anchors' paths differ by round-off at a particle and sum to the same
// length beyond it, the particles beyond keep the anchor that was nearer
// there.
// Unreachable particles get +infinity and anchor -1.
struct NearestAnchors {
  std::vector<Real> distance;
  std::vector<Index> anchor;  // position in `anchors`, or -1
};
NearestAnchors nearest_anchor_paths(const std::vector<Vec3>& x, const std::vector<std::array<Index, 2>>& edges,
                                    const std::vector<Index>& anchors);

}  // namespace xpbd::detail
