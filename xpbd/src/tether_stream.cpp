// The coloured XPBD Tether sweep over its compiled stream
// (distance_stream.hpp, Model::tether_stream; the kernel is
// tether_kernel.hpp), run by the Distance stream's steps (stream.cpp,
// pair_begin_step and pair_sweep): per step the constant factors, per sweep
// the particles copied into the records, projected colour by colour, copied
// back; the multipliers back to State::lambda at the end of the step. With
// `levels`, the same over the stream of Model::tether_levels (the array
// order's levels, step.cpp).
#include <cstddef>

#include "stream.hpp"
#include "tether_kernel.hpp"
#include "xpbd/distance_stream.hpp"
#include "xpbd/workers.hpp"

namespace xpbd {
namespace detail {

void project_tether_scalar(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first) {
  project_tether_variant<ScalarLane>(s, lo, hi, damped, first);
}

namespace {
PairStream tether_pair(const Model& m, State& s, bool levels) {
#if XPBD_HAVE_AVX2_KERNEL
  const PairKernel avx2 = &project_tether_avx2;
#else
  const PairKernel avx2 = nullptr;
#endif
#if XPBD_HAVE_AVX512_KERNEL
  const PairKernel avx512 = &project_tether_avx512;
#else
  const PairKernel avx512 = nullptr;
#endif
  return {levels ? m.tether_level_stream : m.tether_stream,
          levels ? m.tether_levels : m.tether_colours,
          s.tether_at,
          s.tether_inv_den,
          s.tether_gamma,
          s.tether_lambda,
          s.tether_factors,
          &project_tether_scalar,
          avx2,
          avx512};
}
}  // namespace

void tether_begin_step(const Model& m, State& s, Real h, Workers* workers, bool levels) {
  pair_begin_step(m, s, tether_pair(m, s, levels), m.has_damping[type_index_v<Tether>], h, workers);
}

void tether_sweep(const Model& m, State& s, const SolveContext& sc, bool damped, bool simd, bool first,
                  bool pack, Workers* workers, bool levels) {
  pair_sweep(m, s, tether_pair(m, s, levels), sc, damped, simd, first, pack, workers);
}

void tether_end_step(const Model& m, State& s, bool levels) {
  scatter_lambda(levels ? m.tether_levels.order : m.tether_colours.order, s.tether_lambda, s.lambdas<Tether>());
}

DistanceStream make_tether_stream(const Model& m) {
  return make_pair_stream(m.get<Tether>(), m.tether_colours.order, m.inv_mass,
                          [](const Tether& c) { return c.length; });
}

DistanceStream make_tether_level_stream(const Model& m) {
  return make_pair_stream(m.get<Tether>(), m.tether_levels.order, m.inv_mass,
                          [](const Tether& c) { return c.length; });
}

}  // namespace detail
}  // namespace xpbd
