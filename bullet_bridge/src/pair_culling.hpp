#pragma once
// Culling of (particle, body) pairs before the narrowphase (internal to the
// bridge; used by world_contacts.cpp).
//
// The narrowphase reports a contact for particle i and body b only if the
// particle's centre comes within reach_i = r_i + thickness + margin + travel_i
// of b's surface, travel_i = dt (|v_i - v_b| + a_b + w_b extent_b)
// (world_contacts.cpp; a_b = dt |accel_b| is the speed the body gains over the
// step, w_b its angular speed plus what it gains):
// query_point() finds nothing farther than reach_i, and a sweep hit lies on
// the surface within dt |v_i - v_b| <= travel_i of the start point. The
// particle is tested relative to the body's start pose (moved to the pose
// Bullet's shape is at, where the rigid transform keeps distances), and the
// body's shape at the start pose lies inside its AABB there (Bullet's getAabb, the box the
// broadphase itself relies on). So a contact needs
//   dist(x_i, AABB_b) <= reach_i <= half_i + grow_b, with
//   half_i = r_i + thickness + margin + dt |v_i|  and
//   grow_b = dt (|v_b| + a_b + w_b extent_b)      (|v_i - v_b| <= |v_i| + |v_b|),
// and then the cube of half size half_i around x_i overlaps AABB_b grown by
// grow_b (an L-infinity distance never exceeds the Euclidean one). A pair
// whose boxes are apart is skipped; the others go to the narrowphase as
// before, in the same order, so the contacts are the same. grow_b also holds
// a slack of 4 kDegenerateRel relative to the coordinates, for the round-off
// of the transforms and of the narrowphase's own tolerances (at most
// kDegenerateRel relative).
//
// Finding the overlapping boxes: the candidate boxes go into a uniform grid
// (hashed cells, as xpbd/spatial_hash.hpp), each into every cell its box
// grown by grid_reach covers; a particle with half_i <= grid_reach then looks
// at the one cell of its centre only. grid_reach is twice the mean half_i,
// so in a scene that moves as a whole every particle is looked up that way;
// a faster particle, and a candidate box that covers more than kMaxCells
// cells (a ground plane), is tested against all boxes of the other kind. The
// cell size is the median side of the grown candidate boxes (any size is
// correct; this one puts a typical body in about 2 x 2 x 2 cells). Work per
// step: O(n + candidates + pairs), plus n x (wide candidates) box tests.

#include <btBulletDynamicsCommon.h>

#include <array>
#include <vector>

#include "xpbd/spatial_hash.hpp"
#include "xpbd/workers.hpp"
#include "xpbd/types.hpp"

namespace xpbd_bullet::detail {

using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;

// Axis-aligned box (m, world).
struct Box {
  Vec3 lo, hi;
};

// One broadphase candidate of the current step, as the contact loop uses it.
struct Candidate {
  const btCollisionObject* obj = nullptr;
  int shadow = -1;         // index of its shadow (XpbdWorld::shadows_)
  btTransform to_pose;     // world points at the body's start pose -> the same body points where its shape is
  btTransform pose_inv;    // inverse of the pose its shape is at
  Vec3 vb = Vec3::Zero();  // m/s, linear velocity at the start of the step
  Real ab = 0;             // m/s, speed the body gains over the step (dt |accel|)
  Real wb = 0;             // rad/s, angular speed at the start plus what it gains over the step
  Real extent = 0;         // m, diagonal of its AABB
  Box box;                 // m, its AABB at the start pose grown by grow_b
  bool in_grid = false;
  // Found only by its motion (detail::add_moving_candidates), not by the
  // broadphase box: contacts where the particle's path relative to it
  // crosses its surface, or within the margin.
  bool by_motion = false;
};

// False only if the cube of half size `half` (m) around c and the box are
// apart on an axis. A NaN makes every comparison false, so a pair with a NaN
// is never skipped (query_point then reports the bad input, as without
// culling).
inline bool overlaps(const Vec3& c, Real half, const Box& b) {
  for (int a = 0; a < 3; ++a)
    if (c[a] + half < b.lo[a] || c[a] - half > b.hi[a]) return false;
  return true;
}

struct GridEntry {
  xpbd::Cell cell;
  Index candidate = 0;
};

// Per-system scratch of the contact search, reused across steps: it only
// grows (std::vector keeps its capacity through clear/assign/resize).
struct ContactScratch {
  std::vector<Candidate> candidates;
  std::vector<Real> half;              // m, per particle: half_i
  // half_i before widen_for_edges widened it (then `widened`): the
  // particle narrowphase queries only the pairs this half finds.
  std::vector<Real> base_half;
  bool widened = false;
  std::vector<Real> sides;             // m, scratch for the median cell size
  std::vector<GridEntry> entries;      // (cell, candidate) in insertion order
  std::vector<GridEntry> grid;         // the same, grouped by bucket
  std::vector<Index> bucket_begin;     // 2^k + 1 offsets into grid
  std::vector<Index> wide;             // candidates not in the grid
  // (candidate, particle), particles increasing: per piece of the particles
  // (find_pairs), in order.
  std::vector<std::vector<std::array<Index, 2>>> found;
  std::vector<Index> pair_begin;       // per candidate + 1: offsets into particles
  std::vector<Index> particles;        // particles of each candidate, increasing
};

// Fills sc.pair_begin / sc.particles: for every candidate k, the movable
// particles i, in increasing order, whose cube [x_i - half_i, x_i + half_i]
// overlaps candidates[k].box. The grid only finds them faster: the result is
// exactly that box test over all pairs. workers: a pool that tests pieces
// of the particles in parallel (the same result), or null.
void find_pairs(const std::vector<Vec3>& x, const std::vector<Real>& inv_mass, ContactScratch& sc,
                xpbd::Workers* workers = nullptr);

}  // namespace xpbd_bullet::detail
