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

}  // namespace xpbd::detail
