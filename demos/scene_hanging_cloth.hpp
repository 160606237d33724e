#pragma once
// The hanging cloth of the default demo (the seed report's Fig. 5 setup),
// shared by the demo, the benchmarks and any test that wants it.
//
// A square cloth of n x n particles, `size` x `size` metres, total mass `mass`
// over the movable particles, starts flat in the horizontal plane y = 0 and is
// pinned (mass 0, kinematic) at the two corners of its "top" edge (j = 0), so
// it falls and swings down under the pin line x in [-size/2, size/2], z = 0.
// Edges: structural + shear + bending-distance (xpbd::add_cloth_grid), all with
// the same compliance (btSoftBody has a single kLST for every link, so one
// stiffness for all edges keeps the comparison like for like).
#include "xpbd/builders.hpp"
#include "xpbd/scene.hpp"

namespace xpbd_demos {

struct HangingClothParams {
  int n = 32;                            // particles per side (>= 2)
  xpbd::Real size = 1;                   // m, side length
  xpbd::Real mass = 1;                   // kg, total mass of the movable particles
  // XPBD compliance of every edge (m/N). 1e-8 m/N is a spring of 1e8 N/m per
  // edge: at the demo's substep h = 1/600 s, alpha/h^2 = 3.6e-3 1/kg against
  // sum w|grad C|^2 ~ 2000 1/kg, so the edges are effectively inextensible,
  // the same target as btSoftBody's kLST = 1 and PBD's k = 1. The static
  // strain this compliance allows under the cloth's ~10 N weight is ~1e-7;
  // every larger strain the demo measures is solver error.
  xpbd::Real compliance = xpbd::Real(1e-8);
  xpbd::Real pbd_stiffness = 1;          // PBD stiffness k in [0, 1] (Method::pbd only)
};

struct HangingCloth {
  xpbd::SceneDesc scene;
  xpbd::ClothGrid grid;
  xpbd::Real pin_height = 0;  // m, y of the pinned corners
};

HangingCloth make_hanging_cloth(const HangingClothParams& p = {});

}  // namespace xpbd_demos
