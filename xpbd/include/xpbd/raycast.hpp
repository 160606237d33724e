// Ray queries against a particle system's visible surface.
//
// The surface is Model::surface_triangles (filled by the builders), or
// Model::collision_triangles where a model has no surface triangles; a
// model with neither (a rope, loose particles) is never hit. Both sides of
// a triangle are hit. The cost is one test per triangle (no acceleration
// structure): meant for picking and sensing, a few rays per frame.
//
// As Bullet's rayTest: a ray from `from` to `to` hits at a fraction f in
// [0, 1] of the way, the point from + f (to - from); the hit normal is the
// triangle's unit normal turned to face `from`.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "xpbd/model.hpp"
#include "xpbd/state.hpp"
#include "xpbd/types.hpp"

namespace xpbd {

struct RayHit {
  std::size_t triangle = 0;        // index into the triangles hit (see above)
  std::array<Index, 3> particles{};  // the triangle's particles
  // Weights of those particles at the hit point (sum 1, each in [0, 1]):
  // point = w0 x[p0] + w1 x[p1] + w2 x[p2]. To move the hit point, move the
  // particles by these weights (picking).
  std::array<Real, 3> barycentric{};
  Real fraction = 0;   // along from -> to, in [0, 1]
  Real distance = 0;   // m, from `from` to the point
  Vec3 point = Vec3::Zero();   // m
  Vec3 normal = Vec3::Zero();  // unit, facing `from`
};

// The triangles ray queries test for `m`: surface_triangles, or
// collision_triangles if there are none.
const std::vector<std::array<Index, 3>>& ray_triangles(const Model& m);

// Every hit along the segment, nearest first (equal fractions: lower
// triangle index first). Throws xpbd::ConfigError if `from` or `to` is not
// finite, or if the state's particle count is not the model's. A segment of
// zero length, a triangle of zero area, a ray in a triangle's plane, and a
// triangle with a particle that is not finite are never hit.
std::vector<RayHit> ray_hits(const Model& m, const State& s, const Vec3& from, const Vec3& to);
// The nearest hit, if any (same rules).
std::optional<RayHit> ray_closest(const Model& m, const State& s, const Vec3& from, const Vec3& to);

}  // namespace xpbd
