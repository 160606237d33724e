#pragma once
// step()'s use of the direct tree solve (trees.hpp, trees.cpp). Internal.
#include "xpbd/model.hpp"
#include "xpbd/state.hpp"

namespace xpbd::detail {

// The direct solve of every tree of Model::trees for substeps of h: up to
// `passes` Newton passes (each a linearised solve at the current
// positions) while some element's residual |C + alpha/h^2 lambda| is above
// tol times its rest length. `stream`: the Distance multipliers are in
// State::stream_lambda (the coloured XPBD sweep), else in State::lambda.
void trees_solve(const Model& m, State& s, Real h, bool stream, int passes, Real tol);

}  // namespace xpbd::detail
