#pragma once
// step()'s use of the direct chain solve (chains.hpp, chains.cpp). Internal.
#include "xpbd/model.hpp"
#include "xpbd/state.hpp"

namespace xpbd::detail {

// At the start of a step, after the host's attachments are checked: which
// attachment each chain end takes (State::chain), and the scratch sized.
void chains_begin_step(const Model& m, State& s);
// The direct solve of every chain for substeps of h: up to `passes` Newton
// passes (each a linearised solve at the current positions) while some
// row's residual |C + alpha/h^2 lambda| is above tol times its rest length.
// `stream`: the Distance multipliers are in State::stream_lambda (the
// coloured XPBD sweep), else in State::lambda.
void chains_solve(const Model& m, State& s, Real h, bool stream, int passes, Real tol);

// The Newton passes of one chain's or tree's system (chains.cpp,
// trees.cpp): assemble() returns the largest residual over rest length,
// solve() false for a singular system, apply() moves the particles.
template <class System>
void newton_passes(System& sys, int passes, Real tol) {
  for (int pass = 0; pass < passes; ++pass) {
    // Every row's residual within tol of its rest length: done.
    if (!(sys.assemble() > tol)) break;
    // Singular: left to the sweep in this pass (and the next ones, which
    // would meet the same system).
    if (!sys.solve()) break;
    sys.apply();
  }
}

}  // namespace xpbd::detail
