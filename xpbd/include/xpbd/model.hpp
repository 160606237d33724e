#pragma once
// Model: what a scene *is*. Immutable after compile(), shareable between many
// State instances (MuJoCo's mjModel / Jolt's shared settings).
#include <array>
#include <vector>

#include "xpbd/chains.hpp"
#include "xpbd/trees.hpp"
#include "xpbd/constraint_types.hpp"
#include "xpbd/dihedral_stream.hpp"
#include "xpbd/distance_stream.hpp"
#include "xpbd/spatial_hash.hpp"
#include "xpbd/types.hpp"

namespace xpbd {

// A colouring of one constraint type's elements (compile.cpp): element
// indices grouped into colours such that no two elements of one colour share
// a particle, so the projections of one colour are independent of each other
// (StepConfig::coloured). Colours come from a greedy colouring in array
// order (each element takes the smallest colour none of its particles has
// yet); within a colour the elements keep their array order.
struct ColourSchedule {
  std::vector<Index> order;  // element indices, colour by colour
  // Colour c holds order[begin[c]] .. order[begin[c+1] - 1]; size colours + 1
  // (just {0} when the type has no elements).
  std::vector<Index> begin{0};

  Index num_colours() const { return static_cast<Index>(begin.size()) - 1; }
};

struct Model {
  // Particles (parallel arrays, one entry per particle).
  std::vector<Real> inv_mass;  // 1/kg; 0 = kinematic
  std::vector<Real> radius;    // m
  std::vector<Vec3> x0;        // m, initial positions (make_state)
  std::vector<Vec3> v0;        // m/s, initial velocities (make_state)

  std::vector<Plane> planes;   // static planes referenced by Wall elements
  // Triangles rigid features collide with (SceneDesc::collision_triangles).
  std::vector<std::array<Index, 3>> collision_triangles;
  // The visible surface (SceneDesc::surface_triangles): rendering and ray
  // queries only.
  std::vector<std::array<Index, 3>> surface_triangles;
  std::vector<Vec3> pin_target0;  // m, initial pin targets, one per Pin

  ConstraintArrays constraints;   // one flat array per constraint type

  // GlobalVolume surfaces, flat: triangles as indices into
  // global_volume_verts, which holds the particle index of every distinct
  // surface vertex (each GlobalVolume owns a range of both).
  std::vector<std::array<Index, 3>> global_volume_tris;
  std::vector<Index> global_volume_verts;

  // True if any element of that type has damping != 0 (selects the kernel
  // variant that reads previous positions).
  std::array<bool, kNumConstraintTypes> has_damping{};

  // Colour schedule of the Distance elements, and the elements copied in
  // that order (distance_by_colour[j] = Distance element
  // distance_colours.order[j]), which the coloured sweep reads contiguously.
  // Used by StepConfig::coloured.
  ColourSchedule distance_colours;
  std::vector<Distance> distance_by_colour;
  // The same elements compiled for the XPBD kernel (distance_stream.hpp).
  DistanceStream distance_stream;
  // Array order's levels of the Distance elements: element k's level is one
  // more than the highest level of the earlier elements that share a
  // particle with it, and each level keeps array order. A sweep over the
  // levels in turn gives what the array-order sweep gives, bit for bit (but
  // a coordinate of -0 that an element left alone touches may become +0:
  // stream_kernel.hpp): an element still sees every earlier element that
  // moved its particles, and elements of one level share none. step() runs XPBD's array order over
  // this schedule's stream with the vector kernel where that pays
  // (StepConfig::levels, uses_levels; docs/bench-levels.md).
  ColourSchedule distance_levels;
  DistanceStream distance_level_stream;
  // The DihedralBending elements' colour schedule and its compiled form
  // (dihedral_stream.hpp), for the coloured XPBD sweep.
  ColourSchedule dihedral_colours;
  DihedralStream dihedral_stream;
  // The Tether elements' colour schedule and their compiled form
  // (distance_stream.hpp), for the coloured XPBD sweep. Unlike the other
  // schedules, elements of one colour may share a particle whose inverse
  // mass is 0 (an anchor that every tether of a pin shares): it never
  // moves, and the kernel never writes it (tether_kernel.hpp). So this
  // schedule holds for the inverse masses compile() set.
  ColourSchedule tether_colours;
  DistanceStream tether_stream;
  // Array order's levels of the Tether elements and their compiled form,
  // as distance_levels, but for the particles whose inverse mass is 0 (the
  // anchors): no element writes them, so elements that share only such a
  // particle share a level (the same exception as tether_colours).
  ColourSchedule tether_levels;
  DistanceStream tether_level_stream;
  // The Distance elements' chains (chains.hpp) and trees (trees.hpp), for
  // StepConfig::direct_chains.
  Chains chains;
  Trees trees;

  // Opt-in particle-particle collision (spatial_hash.hpp); empty when off.
  SelfCollisionModel self_collision;

  Index num_particles() const { return static_cast<Index>(inv_mass.size()); }

  template <class T>
  const std::vector<T>& get() const {
    return std::get<std::vector<T>>(constraints);
  }
  template <class T>
  std::vector<T>& get() {
    return std::get<std::vector<T>>(constraints);
  }
};

struct SceneDesc;

}  // namespace xpbd
