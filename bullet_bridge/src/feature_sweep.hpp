#pragma once
// Continuous collision of a fast rigid feature point against a cloth
// triangle (XpbdWorld::find_triangle_contacts): does the feature's path
// over the step come within `band` of the triangle, over it?
//
// The path is given as points at equal fractions of the step (start, ...,
// end): the body's screw motion cut into pieces short enough that their
// chords stay close to the arc. The triangle moves in a straight line from
// its corners at the step's start (a) to where they go without contacts
// (b). Each piece is one vertex-face test of FCL's continuous collision
// (fcl::detail::Intersect::intersect_VF: the first time in the piece at
// which the moving point is in the moving triangle's plane and inside it),
// run against the triangle moved by `band` along its normal towards the
// side the feature starts on, so that a hit means the feature enters the
// contact band over the triangle. A feature that starts within the band
// is tested against the triangle itself (it hits when it would cross).
// FCL's types stay in feature_sweep.cpp; it computes in double.
#include <array>

#include "xpbd/types.hpp"

namespace xpbd_bullet::detail {

// side: +1 or -1, the side of the triangle's plane (its normal
// (b - a) x (c - a) at the start) the feature starts on; start_distance:
// the feature's signed distance from that plane at the start.
bool sweep_reaches_triangle(const xpbd::Vec3* path, int points, const std::array<xpbd::Vec3, 3>& a,
                            const std::array<xpbd::Vec3, 3>& b, xpbd::Real side, xpbd::Real start_distance,
                            xpbd::Real band);

}  // namespace xpbd_bullet::detail
