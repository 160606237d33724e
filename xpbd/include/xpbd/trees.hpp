#pragma once
// Direct solve over trees of Distance elements (StepConfig::direct_chains).
//
// Chains (chains.hpp) are paths: a rope. Where three or more undamped
// elements meet at a particle and the structure has no loop (a branched
// rope, a plant, a mobile, a hair strand with its branches), the
// linearised XPBD system of one sweep,
//   (J W J^T + alpha/h^2) dlambda = -C - (alpha/h^2) lambda,
// is no longer tridiagonal, but the equivalent system over the particles'
// moves and the multipliers together,
//   [ M   J^T      ] [ dx ]   [ 0                      ]
//   [ J   -alpha/h^2 ] [ -dlambda ] = [ -C - (alpha/h^2) lambda ],
// has the shape of the structure itself: a tree whose nodes are the moving
// particles and the elements. Eliminated from the leaves to a root it
// takes no fill, so it is solved exactly in time linear in the tree's size
// (Baraff 1996, "Linear-time dynamics using Lagrange multipliers"; the
// tree case of Deul et al. 2018). A heavy weight at the end of one branch
// is then balanced against every branch at once, where Gauss-Seidel and
// the chains' solves, one branch at a time, carry its load across the
// junction a little per sweep.
//
// Particles of inverse mass 0 (pins) are not nodes: an element to a pin
// has one particle node. A particle's other constraints (bending, contacts,
// attachments) stay with the sweep. The chains of a tree's branches are
// still solved as chains, before the tree.
#include <array>
#include <cstddef>
#include <vector>

#include "xpbd/types.hpp"

namespace xpbd {

struct Distance;

// The trees of a model's Distance elements (compile() fills Model::trees).
// Only undamped elements with two different particles, at least one of
// them of inverse mass > 0, are taken. A connected set of them is a tree
// if it has no loop (the particles of inverse mass 0 apart) and some
// moving particle is in three or more of them (else it is a chain). The
// trees hold for the inverse masses compile() set (nothing in the library
// changes Model::inv_mass afterwards; a tree whose masses were changed
// meets a singular block and is left to the sweep).
struct Trees {
  // Tree t has the nodes begin[t] .. begin[t + 1] - 1, every node before
  // its parent, the root last.
  std::vector<Index> begin{0};
  // Per node: the particle (element = 0) or the Distance element
  // (element = 1) it stands for.
  std::vector<Index> index;
  std::vector<char> element;
  // Per node: its parent node (global index), -1 for a root.
  std::vector<Index> parent;
  // Per element node: its position in the coloured stream
  // (Model::distance_colours.order), where the coloured XPBD sweep keeps its
  // multiplier during a step; -1 for a particle node.
  std::vector<Index> stream_slot;
  // The number of Distance elements and particles the trees were found in
  // (step() checks them against the model it is given).
  std::size_t num_distance = 0, num_particles = 0;

  Index size() const { return static_cast<Index>(begin.size()) - 1; }
};

// Finds the trees of `elements` over particles of inverse masses `inv_mass`.
Trees find_trees(const std::vector<Distance>& elements, const std::vector<Real>& inv_mass);

// Scratch of the tree solve (State::tree; internal, sized by the solve).
struct TreeScratch {
  std::vector<Mat3> d3;        // particle nodes: the eliminated diagonal block
  std::vector<Vec3> b3, x3;    // and right-hand side, then the solution (dx)
  std::vector<Real> d1, b1, x1;  // element nodes: the same (x: -dlambda)
  std::vector<Vec3> n;         // element nodes: unit direction from p[1] to p[0]
  std::vector<Real> sign;      // per node: the sign of its coupling with its parent
  // Particle nodes: their elements to pins (local node indices, up to 3),
  // and how many there are.
  std::vector<std::array<Index, 3>> pins;
  std::vector<int> pin_count;
};

}  // namespace xpbd
