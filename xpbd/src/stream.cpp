#include "stream.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iterator>
#include <limits>
#include <string>

#include "stream_kernel.hpp"
#include "xpbd/aligned.hpp"
#include "xpbd/error.hpp"
#include "xpbd/distance_stream.hpp"
#include "xpbd/workers.hpp"

namespace xpbd {
namespace detail {

void project_stream_scalar(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first) {
  project_stream_variant<ScalarLane>(s, lo, hi, damped, first);
}

Simd widest_simd() {
#if XPBD_HAVE_AVX512_KERNEL
  if (__builtin_cpu_supports("avx512f") != 0) return Simd::avx512;
#endif
#if XPBD_HAVE_AVX2_KERNEL
  if (__builtin_cpu_supports("avx2") != 0) return Simd::avx2;
#endif
  return Simd::scalar;
}

namespace {
// set_simd_kernel's cap; every kernel gives the same bits, so a cap changed
// while another thread steps changes its speed only.
std::atomic<int> simd_cap{static_cast<int>(Simd::avx512)};
// No kernel named (set_simd_kernel("auto"), the start): the Distance sweep
// may take the fastest of its vector kernels (distance_avx512_kernel).
std::atomic<bool> simd_auto{true};
// set_simd_kernel("avx512-ymm"): the Distance sweep runs its 256-bit
// AVX-512 kernel.
std::atomic<bool> distance_ymm{false};

const char* simd_name(Simd k) {
  switch (k) {
    case Simd::avx512: return "avx512";
    case Simd::avx2: return "avx2";
    case Simd::scalar: break;
  }
  return "scalar";
}
}  // namespace

Simd simd_level(bool simd) {
  if (!simd) return Simd::scalar;
  static const Simd widest = widest_simd();
  return std::min(widest, static_cast<Simd>(simd_cap.load(std::memory_order_relaxed)));
}

namespace {
// Plain pointers, not the vectors: a store through `out` could change a
// vector's own data pointer as far as the compiler knows, which it then
// loaded again in every iteration (the same holds for pointers captured in
// a lambda that split() hands to the threads: step.cpp, predict_range).
void pack(const Vec3* x, const Real* inv_mass, Real* out, std::size_t lo, std::size_t hi) {
  for (std::size_t i = lo; i < hi; ++i) {
    Real* r = out + 4 * i;
    r[0] = x[i].x(), r[1] = x[i].y(), r[2] = x[i].z(), r[3] = inv_mass[i];
  }
}

void unpack(const Real* px, Vec3* x, std::size_t lo, std::size_t hi) {
  for (std::size_t i = lo; i < hi; ++i) {
    const Real* r = px + 4 * i;
    x[i] = Vec3(r[0], r[1], r[2]);
  }
}
}  // namespace

void size_records(const Model& m, State& s, bool damped) {
  const std::size_t n4 = 4 * static_cast<std::size_t>(m.num_particles());
  if (s.stream_x.size() != n4) s.stream_x.assign(n4, Real(0));
  if (damped && s.stream_x_prev.size() != n4) s.stream_x_prev.assign(n4, Real(0));
}

void pack_records(const Model& m, State& s, bool damped, Workers* workers) {
  Real* const px = s.stream_x.data();
  Real* const pprev = damped ? s.stream_x_prev.data() : nullptr;
  const Vec3* const x = s.x.data();
  const Vec3* const x_prev = s.x_prev.data();
  const Real* const inv_mass = m.inv_mass.data();
  split(workers, s.x.size(), 1, [=](std::size_t lo, std::size_t hi) {
    pack(x, inv_mass, px, lo, hi);
    if (pprev != nullptr) pack(x_prev, inv_mass, pprev, lo, hi);
  }, kMinParticlesPerTask);
}

void unpack_range(State& s, std::size_t lo, std::size_t hi) { unpack(s.stream_x.data(), s.x.data(), lo, hi); }

namespace {
// Elements [lo, hi) of pair_begin_step's factors (gamma: null when
// undamped). No gather (DistanceStream::inv_mass_sum), no aliasing, and a
// division by 1 where den is not > 0, so that the compiler packs each loop.
// GCC 12 keeps the branch unless told that floating-point exceptions are
// not observed (no-trapping-math; the values are the same either way).
// An element left alone (inv_den = 0: den <= 0, or not finite) gets at =
// gamma = 0, so that the Distance kernel's dl is num * 0 = +-0 there with
// no test of its own (stream_kernel.hpp).
#if defined(__GNUC__) && !defined(__clang__)
#define XPBD_PACKED_DIVISION [[gnu::optimize("no-trapping-math")]]
#else
#define XPBD_PACKED_DIVISION
#endif
XPBD_PACKED_DIVISION void step_factors(const Real* __restrict compliance, const Real* __restrict damping,
                                       const Real* __restrict wsum, Real* __restrict at, Real* __restrict gamma,
                                       Real* __restrict inv_den, Real inv_h, Real inv_h2, std::size_t lo,
                                       std::size_t hi) {
  if (gamma != nullptr) {
    for (std::size_t j = lo; j < hi; ++j) {
      at[j] = compliance[j] * inv_h2;
      gamma[j] = (compliance[j] * damping[j]) * inv_h;
      const Real den = (wsum[j] + at[j]) + gamma[j] * wsum[j];
      const bool ok = den > Real(0);
      const Real q = Real(1) / (ok ? den : Real(1));
      inv_den[j] = ok ? q : Real(0);
      const bool used = inv_den[j] > Real(0);  // left alone otherwise (den <= 0, or not finite)
      at[j] = used ? at[j] : Real(0);
      gamma[j] = used ? gamma[j] : Real(0);
    }
  } else {
    for (std::size_t j = lo; j < hi; ++j) {
      at[j] = compliance[j] * inv_h2;
      const Real den = wsum[j] + at[j];
      const bool ok = den > Real(0);
      const Real q = Real(1) / (ok ? den : Real(1));
      inv_den[j] = ok ? q : Real(0);
      at[j] = inv_den[j] > Real(0) ? at[j] : Real(0);  // left alone otherwise (den <= 0, or not finite)
    }
  }
}
}  // namespace

std::uint64_t next_stream_serial() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

void pair_begin_step(const Model& m, State& s, const PairStream& p, bool damped, Real h, Workers* workers) {
  const std::size_t e = p.elements.size();
  size_records(m, s, damped);
  p.lambda.resize(e);
  // The factors depend on the stream, h and damped only: kept from the last
  // step when those are the same (a step at a constant dt and substep
  // count), which saves a pass over five arrays of the elements (at 64^2,
  // 24,000 elements, about a third of a sweep).
  const State::StreamFactors key{p.elements.serial, h, damped};
  if (key.serial != 0 && p.factors.serial == key.serial && p.factors.h == h && p.factors.damped == damped &&
      p.at.size() == e && p.inv_den.size() == e && p.gamma.size() == (damped ? e : 0))
    return;
  p.factors = {};  // until they are computed
  p.at.resize(e);
  p.inv_den.resize(e);
  p.gamma.resize(damped ? e : 0);
  const Real inv_h = Real(1) / h;
  const Real inv_h2 = inv_h * inv_h;
  const DistanceStream& ps = p.elements;
  Real* const at = p.at.data();
  Real* const inv_den = p.inv_den.data();
  Real* const gamma = p.gamma.data();
  split(workers, e, 1, [&](std::size_t lo, std::size_t hi) {
    step_factors(ps.compliance.data(), ps.damping.data(), ps.inv_mass_sum.data(), at, damped ? gamma : nullptr,
                 inv_den, inv_h, inv_h2, lo, hi);
  });
  p.factors = key;
}

void pair_sweep(const Model& m, State& s, const PairStream& p, const SolveContext& sc, bool damped, bool simd,
                bool first, bool pack, Workers* workers) {
  if (pack) pack_records(m, s, damped, workers);
  StreamArgs a;
  a.a = p.elements.a.data();
  a.b = p.elements.b.data();
  a.rest = p.elements.rest.data();
  a.at = p.at.data();
  a.inv_den = p.inv_den.data();
  a.gamma = p.gamma.data();
  a.lambda = p.lambda.data();
  a.x = s.stream_x.data();
  a.x_prev = damped ? s.stream_x_prev.data() : nullptr;
  const Simd level = simd_level(simd);
  const PairKernel k = p.measured && level == Simd::avx512 ? distance_avx512_kernel(p.levels)
                                                           : pick_kernel(level, p.scalar, p.avx2, p.avx512);
  // The colours, then the records back into s.x.
  sweep_colours_then(
      p.colours, sc.reverse, workers, [&](std::size_t lo, std::size_t hi) { k(a, lo, hi, damped, first); },
      p.min_per_task, s.x.size(), [&](std::size_t lo, std::size_t hi) { unpack_range(s, lo, hi); });
}

const DistanceKernels& distance_kernels() {
  static const DistanceKernels k = [] {
    DistanceKernels d{nullptr, nullptr, nullptr};
#if XPBD_HAVE_AVX2_KERNEL
    if (__builtin_cpu_supports("avx2") != 0) d.avx2 = &project_stream_avx2;
#endif
#if XPBD_HAVE_AVX512_KERNEL
    if (__builtin_cpu_supports("avx512f") != 0) {
      if (__builtin_cpu_supports("avx512vl") != 0) d.avx512_ymm = &project_stream_avx512_ymm;
#if XPBD_DOUBLE
      // In float the 512-bit Distance kernel was no faster than the AVX2
      // one (docs/bench-coloured.md, "The AVX-512 kernels"): float has none.
      d.avx512 = &project_stream_avx512;
#endif
    }
#endif
    return d;
  }();
  return k;
}

namespace {
// Of the kernels (the non-null ones), the one that sweeps a test colour
// fastest: kElements disjoint pairs of particle records along x, as a
// cloth row's structural edges, compliant (at = 0.01), swept kRounds times
// by each kernel in turn; the one with the shortest best time. With
// `levels`, each sweep calls the kernel over short runs instead, as the
// array order's levels are (kLevelRuns: the mean level of a grid cloth of
// 16², 32², 64² and 128², docs/bench-levels.md), so that each kernel's
// tail of single elements per run counts. Every kernel gives the same
// bits, so the choice changes the speed only.
PairKernel fastest_of(const std::vector<PairKernel>& kernels, bool levels) {
  constexpr std::size_t kLevelRuns[] = {21, 45, 93, 189};
  constexpr std::size_t kElements = 4096;
  constexpr int kRounds = 16;
  std::vector<Index> a(kElements), b(kElements);
  std::vector<Real> rest(kElements, Real(0.01)), at(kElements, Real(0.01)),
      inv_den(kElements, Real(1) / Real(2.01)), lambda(kElements, Real(0));
  AlignedVector<Real> x(8 * kElements, Real(0));  // the kernels load whole records, aligned (State::stream_x)
  for (std::size_t i = 0; i < kElements; ++i) {
    a[i] = static_cast<Index>(2 * i);
    b[i] = static_cast<Index>(2 * i + 1);
    x[8 * i] = Real(0.02) * Real(i);
    x[8 * i + 4] = Real(0.02) * Real(i) + Real(0.011);
    x[8 * i + 3] = x[8 * i + 7] = Real(1);  // inverse masses
  }
  StreamArgs args;
  args.a = a.data();
  args.b = b.data();
  args.rest = rest.data();
  args.at = at.data();
  args.inv_den = inv_den.data();
  args.lambda = lambda.data();
  args.x = x.data();
  std::vector<double> best(kernels.size(), std::numeric_limits<double>::infinity());
  for (int r = 0; r < kRounds; ++r)
    for (std::size_t w = 0; w < kernels.size(); ++w) {
      const auto t0 = std::chrono::steady_clock::now();
      if (levels) {
        for (std::size_t lo = 0, i = 0; lo < kElements; ++i) {
          const std::size_t hi = std::min(kElements, lo + kLevelRuns[i % std::size(kLevelRuns)]);
          kernels[w](args, lo, hi, false, false);
          lo = hi;
        }
      } else {
        kernels[w](args, 0, kElements, false, false);
      }
      best[w] = std::min(best[w], std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  return kernels[std::size_t(std::min_element(best.begin(), best.end()) - best.begin())];
}
}  // namespace

PairKernel distance_avx512_kernel(bool levels) {
  const DistanceKernels& d = distance_kernels();
  if (!simd_auto.load(std::memory_order_relaxed)) {
    if (d.avx512 != nullptr && !distance_ymm.load(std::memory_order_relaxed)) return d.avx512;
    return d.avx512_ymm != nullptr ? d.avx512_ymm : d.avx2;
  }
  // Measured once per process and shape (function-local statics: the
  // first caller measures, any other waits for it).
  const auto measure = [&d](bool short_runs) {
    std::vector<PairKernel> k;
    for (const PairKernel c : {d.avx2, d.avx512_ymm, d.avx512})
      if (c != nullptr) k.push_back(c);
    if (k.empty()) return PairKernel(&project_stream_scalar);  // not on a CPU with AVX-512F (all have AVX2)
    return k.size() == 1 ? k[0] : fastest_of(k, short_runs);
  };
  if (levels) {
    static const PairKernel fastest_levels = measure(true);
    return fastest_levels;
  }
  static const PairKernel fastest = measure(false);
  return fastest;
}

namespace {
PairStream distance_pair(const Model& m, State& s, bool levels) {
  const DistanceKernels& d = distance_kernels();
  return {levels ? m.distance_level_stream : m.distance_stream,
          levels ? m.distance_levels : m.distance_colours,
          s.stream_at,
          s.stream_inv_den,
          s.stream_gamma,
          s.stream_lambda,
          s.stream_factors,
          &project_stream_scalar,
          d.avx2,
          d.avx512,
          kMinDistancePerTask,
          true,
          levels};
}
}  // namespace

void stream_begin_step(const Model& m, State& s, Real h, Workers* workers, bool levels) {
  pair_begin_step(m, s, distance_pair(m, s, levels), m.has_damping[type_index_v<Distance>], h, workers);
}

void stream_sweep(const Model& m, State& s, const SolveContext& sc, bool damped, bool simd, bool first,
                  bool pack, Workers* workers, bool levels) {
  pair_sweep(m, s, distance_pair(m, s, levels), sc, damped, simd, first, pack, workers);
}

void scatter_lambda(const std::vector<Index>& order, const std::vector<Real>& from, std::vector<Real>& to) {
  for (std::size_t j = 0; j < order.size(); ++j) to[static_cast<std::size_t>(order[j])] = from[j];
}

void stream_end_step(const Model& m, State& s, bool levels) {
  scatter_lambda(levels ? m.distance_levels.order : m.distance_colours.order, s.stream_lambda,
                 s.lambdas<Distance>());
}

DistanceStream make_distance_stream(const Model& m) {
  return make_pair_stream(m.get<Distance>(), m.distance_colours.order, m.inv_mass,
                          [](const Distance& c) { return c.rest; });
}

DistanceStream make_distance_level_stream(const Model& m) {
  return make_pair_stream(m.get<Distance>(), m.distance_levels.order, m.inv_mass,
                          [](const Distance& c) { return c.rest; });
}

void check_inv_mass_sums(const Model& m, const char* who) {
  const auto check = [&](const DistanceStream& p, const char* name) {
    if (p.inv_mass_sum.size() != p.size())
      throw ConfigError(std::string(who) + ": model." + name + ".inv_mass_sum has " +
                        std::to_string(p.inv_mass_sum.size()) + " entries, the stream has " +
                        std::to_string(p.size()) + " elements (use compile)");
  };
  check(m.distance_stream, "distance_stream");
  check(m.tether_stream, "tether_stream");
}

}  // namespace detail

void prepare_stream(const Model& m, State& s, Real h, Workers* workers) {
  if (!(h > Real(0)) || !std::isfinite(h))
    throw ConfigError("prepare_stream: h must be finite and > 0, got " + format_value(double(h)));
  detail::check_inv_mass_sums(m, "prepare_stream");
  if (m.distance_stream.size() != m.get<Distance>().size())
    throw ConfigError("prepare_stream: model.distance_stream covers " + std::to_string(m.distance_stream.size()) +
                      " elements, the model has " + std::to_string(m.get<Distance>().size()) +
                      " Distance elements (use compile)");
  if (m.dihedral_stream.size() != m.get<DihedralBending>().size())
    throw ConfigError("prepare_stream: model.dihedral_stream covers " + std::to_string(m.dihedral_stream.size()) +
                      " elements, the model has " + std::to_string(m.get<DihedralBending>().size()) +
                      " DihedralBending elements (use compile)");
  if (m.tether_stream.size() != m.get<Tether>().size())
    throw ConfigError("prepare_stream: model.tether_stream covers " + std::to_string(m.tether_stream.size()) +
                      " elements, the model has " + std::to_string(m.get<Tether>().size()) +
                      " Tether elements (use compile)");
  detail::stream_begin_step(m, s, h, workers);
  std::fill(s.stream_lambda.begin(), s.stream_lambda.end(), Real(0));
  detail::tether_begin_step(m, s, h, workers);
  std::fill(s.tether_lambda.begin(), s.tether_lambda.end(), Real(0));
  detail::dihedral_begin_step(m, s, h, workers);
  std::fill(s.dihedral_lambda.begin(), s.dihedral_lambda.end(), Real(0));
}

void project_stream(const Model& m, State& s, const SolveContext& sc, bool simd, Workers* workers) {
  const std::size_t e = m.distance_stream.size();
  const bool damped = m.has_damping[type_index_v<Distance>];
  if (s.stream_inv_den.size() != e || s.stream_lambda.size() != e ||
      s.stream_x.size() != 4 * static_cast<std::size_t>(m.num_particles()) ||
      (damped && s.stream_gamma.size() != e))
    throw ConfigError("project_stream: the state's stream is not prepared for this model (call prepare_stream)");
  detail::stream_sweep(m, s, sc, damped, simd, false, true, workers);
}

void project_tether_stream(const Model& m, State& s, const SolveContext& sc, bool simd, Workers* workers) {
  const std::size_t e = m.tether_stream.size();
  const bool damped = m.has_damping[type_index_v<Tether>];
  if (s.tether_inv_den.size() != e || s.tether_lambda.size() != e ||
      s.stream_x.size() != 4 * static_cast<std::size_t>(m.num_particles()) ||
      (damped && (s.tether_gamma.size() != e || s.stream_x_prev.size() != s.stream_x.size())))
    throw ConfigError(
        "project_tether_stream: the state's stream is not prepared for this model (call prepare_stream)");
  detail::tether_sweep(m, s, sc, damped, simd, false, true, workers);
}

const char* simd_kernel() { return detail::simd_name(detail::simd_level(true)); }

const char* distance_kernel(bool levels) {
  using detail::Simd;
  const Simd level = detail::simd_level(true);
  if (level != Simd::avx512) return detail::simd_name(level);
  const detail::PairKernel k = detail::distance_avx512_kernel(levels);
  const detail::DistanceKernels& d = detail::distance_kernels();
  return k == d.avx512 ? "avx512" : k == d.avx512_ymm ? "avx512-ymm" : k == d.avx2 ? "avx2" : "scalar";
}

void set_simd_kernel(const std::string& name) {
  using detail::Simd;
  if (name == "auto") {
    detail::simd_cap.store(static_cast<int>(Simd::avx512), std::memory_order_relaxed);
    detail::simd_auto.store(true, std::memory_order_relaxed);
    detail::distance_ymm.store(false, std::memory_order_relaxed);
    return;
  }
  Simd k = Simd::scalar;
  if (name == "avx512" || name == "avx512-ymm")
    k = Simd::avx512;
  else if (name == "avx2")
    k = Simd::avx2;
  else if (name != "scalar")
    throw ConfigError("set_simd_kernel: unknown kernel \"" + name + "\" (auto, avx512, avx512-ymm, avx2 or scalar)");
  if (k > detail::widest_simd())
    throw ConfigError("set_simd_kernel: \"" + name + "\" is not available here (the widest kernel of this build on this CPU is " +
                      detail::simd_name(detail::widest_simd()) + ")");
  const bool ymm = name == "avx512-ymm";
  if (ymm && detail::distance_kernels().avx512_ymm == nullptr)
    throw ConfigError("set_simd_kernel: \"avx512-ymm\" is not available here (this CPU does not report AVX-512VL)");
  detail::simd_cap.store(static_cast<int>(k), std::memory_order_relaxed);
  detail::simd_auto.store(false, std::memory_order_relaxed);
  detail::distance_ymm.store(ymm, std::memory_order_relaxed);
}

}  // namespace xpbd
