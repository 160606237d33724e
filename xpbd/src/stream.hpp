#pragma once
// step()'s use of the compiled streams (distance_stream.hpp,
// dihedral_stream.hpp): the coloured XPBD Distance, Tether and
// DihedralBending stages of one sweep, on the calling thread or over Workers.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "xpbd/model.hpp"
#include "xpbd/solve.hpp"
#include "xpbd/state.hpp"
#include "xpbd/workers.hpp"

namespace xpbd {
namespace detail {

// --- Shared by both streams (stream.cpp) ---

// Calls f(lo, hi) over [0, n) in contiguous pieces whose bounds are
// multiples of `align` (so that vector batches stay whole), on the workers
// when there are several and n is at least 2 * kMinPerTask.
constexpr std::size_t kMinPerTask = 256;
// The passes over the particles (the prediction, the velocity update, the
// records' copies): from 2 x 1024 particles on. With this and
// kMinDistancePerTask (below) two threads went from 0.74-0.75x one thread
// to 0.93-0.95x on a 32 x 32 cloth, and were unchanged from 64 x 64 up;
// either alone changed nothing (docs/bench-threads.md, "Where threads start
// to pay").
constexpr std::size_t kMinParticlesPerTask = 1024;

// How many pieces split() cuts n elements into, and where piece t of them
// begins (piece `tasks` is the end, n).
inline int split_tasks(const Workers* w, std::size_t n, std::size_t min_per_task) {
  if (w == nullptr || n < 2 * min_per_task) return 1;
  return std::min(w->threads(), static_cast<int>(n / min_per_task));
}
inline std::size_t split_bound(std::size_t n, int tasks, int t, std::size_t align) {
  if (t == tasks) return n;
  const std::size_t b = n * static_cast<std::size_t>(t) / static_cast<std::size_t>(tasks);
  return b - b % align;
}

template <class F>
void split(Workers* w, std::size_t n, std::size_t align, F&& f, std::size_t min_per_task = kMinPerTask) {
  const int tasks = split_tasks(w, n, min_per_task);
  if (tasks <= 1) {
    f(std::size_t(0), n);
    return;
  }
  auto task = [&](int t) { f(split_bound(n, tasks, t, align), split_bound(n, tasks, t + 1, align)); };
  w->run(tasks, std::ref(task));  // std::ref: no allocation
}

// Calls kernel(lo, hi) over each colour of `cs` in turn (last to first if
// `reverse`), each split over the workers in pieces whose bounds are
// multiples of 16 (whole vector batches of every kernel), then after(lo,
// hi) over [0, after_n) split as split() splits a pass over the particles
// (the records' copy back). A colour is split only from 2 * min_per_task
// elements on. On a pool the colours and the pass are the phases of one
// Workers::run_phases job: the same pieces as split() gives each (so the
// same bits), with one wake-up of the helpers per sweep instead of one per
// colour.
template <class K, class A>
void sweep_colours_then(const ColourSchedule& cs, bool reverse, Workers* workers, K&& kernel,
                        std::size_t min_per_task, std::size_t after_n, A&& after) {
  const Index colours = cs.num_colours();
  const auto colour = [&](Index j) { return static_cast<std::size_t>(reverse ? colours - 1 - j : j); };
  if (workers == nullptr || workers->threads() < 2) {
    for (Index j = 0; j < colours; ++j) {
      const std::size_t c = colour(j);
      kernel(static_cast<std::size_t>(cs.begin[c]), static_cast<std::size_t>(cs.begin[c + 1]));
    }
    if (after_n > 0) after(std::size_t(0), after_n);
    return;
  }
  // Tasks per phase; kept, so that a sweep allocates nothing. A reference:
  // the helpers must read the calling thread's.
  thread_local std::vector<int> kept;
  std::vector<int>& tasks = kept;
  tasks.resize(static_cast<std::size_t>(colours) + (after_n > 0 ? 1 : 0));
  for (Index j = 0; j < colours; ++j) {
    const std::size_t c = colour(j);
    tasks[static_cast<std::size_t>(j)] =
        split_tasks(workers, static_cast<std::size_t>(cs.begin[c + 1] - cs.begin[c]), min_per_task);
  }
  if (after_n > 0) tasks.back() = split_tasks(workers, after_n, kMinParticlesPerTask);
  auto piece = [&](int j, int t) {
    const int k = tasks[static_cast<std::size_t>(j)];
    if (j == colours) {
      after(split_bound(after_n, k, t, 1), split_bound(after_n, k, t + 1, 1));
      return;
    }
    const std::size_t c = colour(j);
    const auto b = static_cast<std::size_t>(cs.begin[c]), n = static_cast<std::size_t>(cs.begin[c + 1]) - b;
    kernel(b + split_bound(n, k, t, 16), b + split_bound(n, k, t + 1, 16));
  };
  workers->run_phases(tasks, std::ref(piece));  // std::ref: no allocation
}

template <class K>
void sweep_colours(const ColourSchedule& cs, bool reverse, Workers* workers, K&& kernel,
                   std::size_t min_per_task = kMinPerTask) {
  sweep_colours_then(cs, reverse, workers, kernel, min_per_task, 0, [](std::size_t, std::size_t) {});
}

// to[order[j]] = from[j]: multipliers from stream order back to the
// elements' order.
void scatter_lambda(const std::vector<Index>& order, const std::vector<Real>& from, std::vector<Real>& to);

// The kernels of the coloured sweeps, narrowest first.
enum class Simd { scalar = 0, avx2 = 1, avx512 = 2 };
// The kernel the sweeps run: scalar unless `simd`; else the widest that
// this build has, this CPU reports and set_simd_kernel allows.
Simd simd_level(bool simd);
// The widest kernel this build has and this CPU reports.
Simd widest_simd();
// Of the three kernels (any may be null but the scalar one), the one for
// `level`, or the widest narrower one that exists.
template <class K>
K pick_kernel(Simd level, K scalar, K avx2, K avx512) {
  if (level == Simd::avx512 && avx512 != nullptr) return avx512;
  if (level >= Simd::avx2 && avx2 != nullptr) return avx2;
  return scalar;
}
// State::stream_x (and stream_x_prev when damped) sized for m's particles.
void size_records(const Model& m, State& s, bool damped);
// x (and x_prev when damped) with 1/m into the records.
void pack_records(const Model& m, State& s, bool damped, Workers* workers);
// The records' positions back into s.x, particles [lo, hi) (the last
// phase of a sweep: sweep_colours_then).
void unpack_range(State& s, std::size_t lo, std::size_t hi);

// A pair stream (the Distance or the Tether one: a DistanceStream in the
// order of its ColourSchedule) with its scratch in State and its kernels.
struct StreamArgs;
using PairKernel = void (*)(const StreamArgs&, std::size_t, std::size_t, bool, bool);
struct PairStream {
  const DistanceStream& elements;
  const ColourSchedule& colours;
  std::vector<Real>& at;
  std::vector<Real>& inv_den;
  std::vector<Real>& gamma;
  std::vector<Real>& lambda;
  State::StreamFactors& factors;  // what at, inv_den and gamma hold (pair_begin_step)
  PairKernel scalar, avx2, avx512;  // null where the library has no such kernel
  // The least elements of a colour per thread (sweep_colours).
  std::size_t min_per_task = kMinPerTask;
  // The Distance stream's: where the CPU allows AVX-512, its kernel is
  // distance_avx512_kernel's choice, not simply the widest.
  bool measured = false;
  // The Distance stream of the array order's levels (short colours): its
  // choice is measured on short runs (distance_avx512_kernel).
  bool levels = false;
};
// The Distance kernels, null where this build or CPU has none: AVX2,
// AVX-512 at 256 bits (AVX-512VL, stream_avx512_ymm.cpp) and at 512 bits
// (double only).
struct DistanceKernels {
  PairKernel avx2, avx512_ymm, avx512;
};
const DistanceKernels& distance_kernels();
// The Distance kernel where the CPU allows AVX-512 (simd_level): the one
// set_simd_kernel named ("avx512": 512 bits, or 256 where there is no
// 512-bit one, as in float; "avx512-ymm": 256 bits), else the one of
// distance_kernels() that sweeps a test colour fastest on this CPU,
// measured at the first call and kept for the process (stream.cpp). On
// an AMD EPYC (Zen 4) the 256-bit AVX-512 kernel was the fastest, and the
// 512-bit one 0.8 times as fast as AVX2; on an Intel Xeon the 512-bit one
// was 1.3-1.5 times as fast as AVX2 (docs/bench-coloured.md). With
// `levels` the measure sweeps short runs, the shape of the array order's
// levels (tens to hundreds of elements each): there the 512-bit kernel's
// groups of 16 leave up to 15 elements per level to its scalar tail
// (docs/bench-levels.md, "The kernel of the levels").
PairKernel distance_avx512_kernel(bool levels = false);
// The Distance colours' threshold: 256 elements are about 0.75 us of
// AVX-512 work, as much as handing out an empty job to two threads (about
// 0.75 us); see kMinParticlesPerTask.
constexpr std::size_t kMinDistancePerTask = 768;
// Sizes the scratch and computes each element's at, 1/den and gamma for
// substeps of h (one element at a time; the same operations in every build).
void pair_begin_step(const Model& m, State& s, const PairStream& p, bool damped, Real h, Workers* workers);
// One sweep, colour by colour (see stream_sweep below).
void pair_sweep(const Model& m, State& s, const PairStream& p, const SolveContext& sc, bool damped, bool simd,
                bool first, bool pack, Workers* workers);

// --- The Distance stream (stream.cpp) ---

// Each of these runs the Distance stream of m.distance_colours, or with
// `levels` that of m.distance_levels (array order's levels: step() runs
// XPBD's array order that way where it pays). A step uses one of the two
// throughout: they share the scratch in State.
//
// Sizes the stream scratch of `s` (no allocation after the first step) and
// computes each element's at, 1/den and gamma for substeps of h: at the
// start of every step.
void stream_begin_step(const Model& m, State& s, Real h, Workers* workers, bool levels = false);
// One sweep of the Distance elements, colour by colour (last to first for
// sc.reverse): particles copied into State::stream_x, projected, copied
// back. `first`: the first sweep of a substep, which takes every multiplier
// as 0 and writes them all (so they need no zeroing at the substep's
// start). `pack`: copy the particles into the records first; false when
// they already hold the positions (step() knows when: after another stream
// stage's copy back, with nothing moved since). `workers` may be null.
void stream_sweep(const Model& m, State& s, const SolveContext& sc, bool damped, bool simd, bool first,
                  bool pack, Workers* workers, bool levels = false);
// State::lambda of Distance from the stream multipliers: at the end of a step.
void stream_end_step(const Model& m, State& s, bool levels = false);
// The compiled stream of m's Distance elements in m.distance_colours order,
// and in m.distance_levels order.
DistanceStream make_distance_stream(const Model& m);
DistanceStream make_distance_level_stream(const Model& m);

// Throws ConfigError, naming `who`, if the Distance or Tether stream lacks
// its inv_mass_sum (a Model not made by compile).
void check_inv_mass_sums(const Model& m, const char* who);

// A number no stream of this process had before (DistanceStream::serial).
std::uint64_t next_stream_serial();

// A pair stream of `es` in `order` (inv_mass: the model's, for
// inv_mass_sum); rest(e) is an element's rest value.
template <class T, class Rest>
DistanceStream make_pair_stream(const std::vector<T>& es, const std::vector<Index>& order,
                                const std::vector<Real>& inv_mass, Rest rest) {
  DistanceStream ps;
  ps.serial = next_stream_serial();
  const std::size_t n = order.size();
  ps.a.resize(n), ps.b.resize(n), ps.rest.resize(n), ps.compliance.resize(n), ps.damping.resize(n);
  ps.inv_mass_sum.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const T& c = es[static_cast<std::size_t>(order[j])];
    ps.a[j] = c.p[0], ps.b[j] = c.p[1], ps.rest[j] = rest(c);
    ps.compliance[j] = c.mat.compliance, ps.damping[j] = c.mat.damping;
    ps.inv_mass_sum[j] = inv_mass[static_cast<std::size_t>(c.p[0])] + inv_mass[static_cast<std::size_t>(c.p[1])];
  }
  return ps;
}

// --- The Tether stream (tether_stream.cpp), the same steps ---

void tether_begin_step(const Model& m, State& s, Real h, Workers* workers, bool levels = false);
void tether_sweep(const Model& m, State& s, const SolveContext& sc, bool damped, bool simd, bool first,
                  bool pack, Workers* workers, bool levels = false);
void tether_end_step(const Model& m, State& s, bool levels = false);
DistanceStream make_tether_stream(const Model& m);
DistanceStream make_tether_level_stream(const Model& m);

// --- The DihedralBending stream (dihedral_stream.cpp), the same steps ---

void dihedral_begin_step(const Model& m, State& s, Real h, Workers* workers);
void dihedral_sweep(const Model& m, State& s, const SolveContext& sc, bool damped, bool simd, bool first,
                    bool pack, Workers* workers);
void dihedral_end_step(const Model& m, State& s);
DihedralStream make_dihedral_stream(const Model& m);

}  // namespace detail
}  // namespace xpbd
