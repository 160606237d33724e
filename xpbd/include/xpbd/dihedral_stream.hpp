#pragma once
// The compiled form of the coloured DihedralBending sweep
// (StepConfig::coloured, XPBD), like the Distance stream
// (distance_stream.hpp): the hinges in the order of Model::dihedral_colours
// (no two hinges of a colour share a particle), as parallel arrays, so that
// a vector kernel reads 4 or 8 hinges of a colour at once. A
// DihedralBending element is 64 bytes in double; its stream entry is 56
// (four particle indices, rest angle, compliance, damping).
//
// The kernel reads the particle records (x, y, z, 1/m) of
// State::stream_x, the same records as the Distance stream, packed before
// the stage (unless the stage before it left them holding the positions)
// and copied back after it. Per hinge it computes what
// solve_dihedral.hpp's kernel computes (the update of DihedralBending in
// constraints_bending.hpp), with the triple product e.(d2 x d3) taken as
// d2.N2 (one cross product fewer). The multipliers are kept in stream
// order in State::dihedral_lambda and copied to State::lambda at the end of
// every step; compliance/h^2 and compliance*damping/h are computed once per
// step (prepare_stream). Unlike a distance, a hinge's denominator depends
// on the positions, so each hinge divides four times per sweep.
//
// The AVX-512 kernel (8 doubles or 16 floats), the AVX2 kernel (4 doubles
// or 8 floats) and the scalar one do the same operations in the same order
// without fused multiply-adds, the angle included (one polynomial atan2 in
// plain arithmetic, src/lane_atan2.hpp), so they give the same results bit
// for bit (tests/unit/test_dihedral_stream.cpp).
#include <vector>

#include "xpbd/types.hpp"

namespace xpbd {

struct Model;
struct State;
struct SolveContext;
class Workers;

struct DihedralStream {
  std::vector<Index> p0, p1, p2, p3;  // particles of element order[j]
  std::vector<Real> rest;             // rad
  std::vector<Real> compliance;       // rad^2/J
  std::vector<Real> damping;          // s (Material::damping)

  std::size_t size() const { return p0.size(); }
};

// One sweep of m's DihedralBending elements over the stream, colour by
// colour (last to first for sc.reverse), as step() runs it with coloured
// XPBD: the widest kernel if `simd` (simd_kernel()), else the scalar one;
// over `workers` when given. prepare_stream (distance_stream.hpp) must have
// been called for this model, state and substep h; it also zeroes the
// multipliers, s.dihedral_lambda[j] for element m.dihedral_colours.order[j].
// Throws ConfigError if the state is not prepared.
void project_dihedral_stream(const Model& m, State& s, const SolveContext& sc, bool simd,
                             Workers* workers = nullptr);

}  // namespace xpbd
