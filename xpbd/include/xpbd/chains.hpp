#pragma once
// Direct solve along chains (StepConfig::direct_chains).
//
// A chain is a path of Distance elements whose inner particles belong to
// exactly two Distance elements: a rope, a rod's centre line, a strand. Along
// a chain, the linearised XPBD system of one sweep,
//   (J W J^T + alpha/h^2) dlambda = -C - (alpha/h^2) lambda,
// is tridiagonal (each element shares one particle with the next), so it is
// solved exactly in time linear in the chain's length (the tree case of
// Deul et al. 2018, "Direct position-based solver for stiff rods", for a
// path). One Gauss-Seidel sweep moves a correction one element along the
// chain; the direct solve moves it the whole length, and balances a heavy
// end against the whole chain at once.
//
// A chain end that carries exactly one BodyAttachment (State::attachments)
// takes the attachment as one more row of the same system, with the body's
// inverse mass along the row (its rotation included): a rope holding a heavy
// body is solved with the body in it. An end attached to the same body as
// the chain's other end keeps that attachment out (the two rows would be
// coupled through the body, and the system would no longer be tridiagonal).
#include <cstddef>
#include <vector>

#include "xpbd/types.hpp"

namespace xpbd {

struct Distance;

// The chains of a model's Distance elements (compile() fills
// Model::chains). Only undamped elements (damping = 0) are taken: an element
// with damping ends a chain and stays with the sweep. A closed loop (every
// particle in two elements, or a path back to the particle it left) is not
// a chain. Chains of one element are not
// kept (the sweep solves one element exactly already).
struct Chains {
  // Chain c has the elements element[begin[c]] .. element[begin[c + 1] - 1]
  // in path order, and the particles particle[begin[c] + c] ..
  // particle[begin[c + 1] + c]: element j joins particles j and j + 1 of
  // its chain.
  std::vector<Index> begin{0};
  std::vector<Index> element;
  std::vector<Index> particle;
  // Per entry of `element`: its position in the coloured stream
  // (Model::distance_colours.order), where the coloured XPBD sweep keeps its
  // multiplier during a step.
  std::vector<Index> stream_slot;
  // Per particle: 2c if it is the first particle of chain c, 2c + 1 if it is
  // the last one, -1 otherwise. Empty when there is no chain.
  std::vector<Index> end_of;
  // The number of Distance elements the chains were found in (step() checks
  // it against the model it is given).
  std::size_t num_distance = 0;

  Index size() const { return static_cast<Index>(begin.size()) - 1; }
};

// Finds the chains of `elements` over `num_particles` particles.
Chains find_chains(const std::vector<Distance>& elements, Index num_particles);

// Scratch of the direct solve (State::chain; internal, sized by step()).
struct ChainScratch {
  std::vector<Index> end_attachment;  // per chain end (2c, 2c + 1): attachment index, or -1
  std::vector<Vec3> n;                // per row: unit direction from its first node to its second
  std::vector<Real> diag, off, rhs, c, d;
};

}  // namespace xpbd
