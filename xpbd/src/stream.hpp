#pragma once
// step()'s use of the DistanceStream (distance_stream.hpp): the coloured
// XPBD Distance stage of one sweep, on the calling thread or over Workers.
#include "xpbd/model.hpp"
#include "xpbd/solve.hpp"
#include "xpbd/state.hpp"

namespace xpbd {
class Workers;
namespace detail {

// Sizes the stream scratch of `s` (no allocation after the first step) and
// computes each element's at, 1/den and gamma for substeps of h: at the
// start of every step.
void stream_begin_step(const Model& m, State& s, Real h, Workers* workers);
// One sweep of the Distance elements, colour by colour (last to first for
// sc.reverse): particles copied into State::stream_x, projected, copied
// back. `first`: the first sweep of a substep, which takes every multiplier
// as 0 and writes them all (so they need no zeroing at the substep's
// start). `workers` may be null.
void stream_sweep(const Model& m, State& s, const SolveContext& sc, bool damped, bool simd, bool first,
                  Workers* workers);
// State::lambda of Distance from the stream multipliers: at the end of a step.
void stream_end_step(const Model& m, State& s);
// The compiled stream of m's Distance elements in m.distance_colours order.
DistanceStream make_distance_stream(const Model& m);

}  // namespace detail
}  // namespace xpbd
