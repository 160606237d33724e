#pragma once
// Hierarchical position-based dynamics (Mueller 2008; StepConfig::hierarchy):
// coarse levels over the Distance elements' graph whose stretch is removed
// before each substep's sweep, so that a correction crosses a large cloth or
// a long rope in one pass per level instead of one element per sweep.
//
// Levels. Level 0 is the particles of the Distance elements, with the
// elements as edges (rest length, the element's). A coarser level's
// particles are a maximal independent set of the finer level's graph,
// chosen greedily: particles of inverse mass 0 first (so that pins anchor
// the coarse levels too), then in index order. Every other particle of the
// finer level (a child) has at least one neighbour in the set (its
// parents, the 16 nearest by rest length where it has more); its weight
// towards parent j is proportional to 1 / rest(i, j), normalised to sum 1. Two coarse particles with a child in common are
// joined by a coarse edge whose rest length is the shortest rest path
// through such a child (rest(p, i) + rest(i, q)): never shorter than the
// straight distance the finer edges allow, and equal to it where the path
// is straight (along a row of a grid, along a rope). A coarse particle's
// mass is its own plus each movable child's times the child's weight
// towards it; inverse mass 0 stays 0. Levels are built while the set
// shrinks below 90 % of the finer level and holds at least 8 particles, at
// most 12 levels.
//
// The pass (before the sweeps of every substep): from the coarsest level
// to the finest, each coarse edge stretched beyond rest * (1 + slack) is
// projected once, without compliance, to rest * (1 + slack) (a
// one-sided constraint: a fold or a compression is left alone); then every
// movable child of the level below moves by the weighted mean of its
// parents' displacements since the pass began. The fine sweep follows as
// without the hierarchy. Nothing moves where no coarse edge is stretched
// beyond the slack, so a structure whose elastic strain stays below the
// slack is solved exactly as without it, and its multipliers (the forces
// read from them) are unchanged; where a coarse edge is stretched beyond
// it, the pass's displacement is not in any multiplier.
#include <array>
#include <memory>
#include <vector>

#include "xpbd/types.hpp"

namespace xpbd {

struct Model;
struct State;

namespace detail {

struct HierarchyLevel {
  std::vector<Index> particles;              // this level's, model indices
  std::vector<Real> inv_mass;                // per entry of particles
  std::vector<std::array<Index, 2>> edges;   // positions in `particles`
  std::vector<Real> rest;                    // per edge, m
  // The finer level's particles that are not in this one, as model indices,
  // each with its parents (model indices) and weights in
  // parent[parent_begin[k] .. parent_begin[k + 1]).
  std::vector<Index> child;
  std::vector<Index> parent_begin{0};
  std::vector<Index> parent;
  std::vector<Real> weight;
};

struct Hierarchy {
  Index num_particles = 0;   // of the model it was built for
  std::size_t num_distance = 0;
  std::vector<HierarchyLevel> levels;  // finest coarse level first
};

// Builds the levels of m's Distance graph (empty levels when it has none).
std::shared_ptr<const Hierarchy> build_hierarchy(const Model& m);

// The pass over s.x for one substep; builds s.hierarchy first if it is
// missing or was built for another model's size.
void hierarchy_pass(const Model& m, State& s, Real slack);

}  // namespace detail
}  // namespace xpbd
