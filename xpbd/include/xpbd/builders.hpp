#pragma once
// Scene builders shared by demos, tests and benchmarks. Each appends particles
// and only the constraint types asked for to a SceneDesc.
#include <vector>

#include "xpbd/scene.hpp"

namespace xpbd {

// A rectangular cloth of nx * ny particles in the plane through `origin`
// spanned by axes u (along x index) and v (along y index), total size
// size_u * size_v metres. Particle (i, j) has index first + j*nx + i.
struct ClothGridDesc {
  int nx = 32, ny = 32;                 // particles per side, >= 2
  Real size_u = 1, size_v = 1;          // m
  Vec3 origin = Vec3::Zero();           // m, position of particle (0, 0)
  Vec3 u = Vec3::UnitX(), v = -Vec3::UnitY();  // in-plane axes (unit, orthogonal)
  Real mass = 1;                        // kg, total over all movable particles
  Real radius = 0;                      // m, particle thickness
  Material stretch;                     // structural edges (i,j)-(i+1,j), (i,j)-(i,j+1)
  bool shear = true;                    // diagonals of every quad
  Material shear_mat;
  bool bend_distance = true;            // (i,j)-(i+2,j), (i,j)-(i,j+2)
  Material bend_mat;
  // Pinned particles, by (i, j). Pinned particles get mass 0 (kinematic).
  std::vector<std::pair<int, int>> pinned;
};

struct ClothGrid {
  Index first = 0;  // index of particle (0, 0)
  int nx = 0, ny = 0;
  Index at(int i, int j) const { return first + j * nx + i; }
};

ClothGrid add_cloth_grid(SceneDesc& scene, const ClothGridDesc& d);

// A chain of n particles from `start` along `dir` (unit) with spacing
// `spacing` (m), each of mass `mass` (kg), joined by distance constraints.
// If pin_first, particle 0 has mass 0 and a kinematic pin.
struct RopeDesc {
  int n = 20;
  Vec3 start = Vec3::Zero();
  Vec3 dir = -Vec3::UnitY();
  Real spacing = Real(0.01);
  Real mass = 1;
  Real radius = 0;
  bool pin_first = true;
  Material mat;
};

// Returns the index of the first particle.
Index add_rope(SceneDesc& scene, const RopeDesc& d);

}  // namespace xpbd
