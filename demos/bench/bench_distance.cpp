// Distance-constraint projection benchmark (docs/design.md section 7).
//
// Scene: a 64 x 64 cloth (1 m x 1 m, 1 kg, two corners pinned) built with
// xpbd::add_cloth_grid, the builder demos and tests use. Its distance set is
// structural + shear + bending-distance edges: 8064 + 7938 + 7936 = 23938.
//
// Every benchmark reports ns_per_projection (one projection = one constraint
// element visited once by the solver):
//   kernel_sweep/*  one Gauss-Seidel sweep of xpbd::project_all<Distance>
//                   over all distance constraints (what step() runs: the
//                   pair-distance kernel of solve.hpp);
//   generic_sweep/* the same sweep through project_all_generic, the
//                   eval()-based kernel every other constraint type uses;
//   naive_sweep/*   the same sweep written as a straightforward scalar loop
//                   over an array of structs (reference, below);
//   coloured_sweep/* one sweep of xpbd::project_all_coloured, what step()
//                   runs with StepConfig::coloured: the pair-distance kernel
//                   over the elements in the order of the model's colour
//                   schedule (Model::distance_by_colour), so consecutive
//                   projections share no particle;
//   stream_sweep/*  one sweep of xpbd::project_stream, what step() runs with
//                   StepConfig::coloured in XPBD: the same order over the
//                   compiled stream (distance_stream.hpp), with the widest
//                   kernel this CPU has (simd_kernel(): AVX-512 or AVX2),
//                   the particles copied in and out included
//                   (prepare_stream, which step() runs once per step, is
//                   not timed);
//   stream_avx2_sweep/* the same capped at the AVX2 kernel
//                   (set_simd_kernel), on a CPU with AVX-512 only;
//   stream_scalar_sweep/* the same with the scalar kernel (simd = false);
//   step/*          a full xpbd::step() of the cloth scene in array order,
//                   element by element (StepConfig::levels off: the
//                   array-order step before the levels), time divided by
//                   substeps * iterations * constraints (so predict and the
//                   velocity update are charged to the projections);
//   step_levels/*   the same step as step/* bit for bit, over array order's
//                   levels with the widest kernel (StepConfig::levels, the
//                   default);
//   step_coloured/* the same with StepConfig::coloured (the stream, widest
//                   kernel);
//   step_coloured_avx2/* the same capped at AVX2, on a CPU with AVX-512 only;
//   step_coloured_scalar/* the same with StepConfig::simd = false;
//   step_threads2/* step_coloured with StepConfig::workers of 2 threads
//                   (wall time).
// XPBD_BENCH_SIMD=avx512-ymm (or any name xpbd::set_simd_kernel takes) in
// the environment runs the rows without an AVX2 cap at that kernel
// (simd_cap.hpp): the way to time one Distance kernel against another.
// At the end the program prints the medians (or single runs), the ratio of
// the naive sweep to each benchmark, for the coloured ones the ratio of the
// array-order benchmark (kernel_sweep or step) to them, and in the last
// column the ratio of a second reference: the scalar kernel's time over the
// vector kernel's (stream_sweep, step_coloured), the single-threaded step's
// over the threaded one's (step_threads2); where the CPU has AVX-512, a
// last column with the AVX2 kernel's time over the widest one's
// (stream_sweep, step_coloured); all measured in this run, and the number
// of colours.
//
// Snapshot / restore (docs/design.md principle 7): the cloth is warmed up by a few
// steps of free swinging; that State is the snapshot. Each measured batch
// first restores the snapshot (untimed), so every timed sweep or step starts
// from the same configuration and does the same work.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "simd_cap.hpp"
#include "xpbd/distance_stream.hpp"
#include "xpbd/solve.hpp"
#include "xpbd/workers.hpp"
#include "xpbd/xpbd.hpp"

namespace {

using namespace xpbd;
using Clock = std::chrono::steady_clock;

constexpr int kGrid = 64;
constexpr int kWarmupSteps = 30;  // 0.5 s at 60 Hz: the cloth is folding and swinging

enum class Stiffness { compliant, rigid, damped };

const char* name(Stiffness s) {
  switch (s) {
    case Stiffness::compliant: return "compliant";
    case Stiffness::rigid: return "rigid";
    case Stiffness::damped: return "damped";
  }
  return "?";
}

// The benchmark scene and its warm snapshot. `sweep_x` is the warm state's
// positions advanced by one prediction (x + h v + h^2 g), i.e. what the first
// sweep of a substep sees; lambda starts at zero as after reset_multipliers().
struct ClothBench {
  Model model;
  StepConfig cfg;
  State snapshot;
  std::vector<Vec3> sweep_x;
  std::vector<Vec3> sweep_x_prev;
};

ClothBench build(Stiffness stiffness) {
  SceneDesc scene;
  ClothGridDesc d;
  d.nx = d.ny = kGrid;
  d.size_u = d.size_v = 1;
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();  // horizontal: it falls and swings from two corners
  d.mass = 1;
  d.pinned = {{0, 0}, {kGrid - 1, 0}};
  if (stiffness != Stiffness::rigid) {
    // m/N. Realistic orders for a 1 kg, 1 m cloth with 1.6 cm edges; the
    // cost of a projection does not depend on the value, only on 0 or not.
    d.stretch.compliance = Real(1e-6);
    d.shear_mat.compliance = Real(1e-5);
    d.bend_mat.compliance = Real(1e-4);
  }
  if (stiffness == Stiffness::damped) {
    // N*s/m; gamma = alpha*beta/h stays O(1e-3..1e-1), a mild damping.
    d.stretch.damping = d.shear_mat.damping = d.bend_mat.damping = Real(10);
  }
  add_cloth_grid(scene, d);

  ClothBench b;
  b.model = compile(scene);
  b.cfg.substeps = 10;
  b.cfg.iterations = 1;
  State s = make_state(b.model);
  for (int i = 0; i < kWarmupSteps; ++i) step(b.model, s, b.cfg);
  b.snapshot = s;

  const Real h = b.cfg.dt / Real(b.cfg.substeps);
  b.sweep_x_prev = s.x;
  b.sweep_x = s.x;
  for (std::size_t i = 0; i < s.x.size(); ++i)
    if (b.model.inv_mass[i] > Real(0)) b.sweep_x[i] += h * (s.v[i] + h * b.cfg.gravity);
  return b;
}

const ClothBench& cloth(Stiffness s) {
  static const ClothBench c[3] = {build(Stiffness::compliant), build(Stiffness::rigid),
                                  build(Stiffness::damped)};
  return c[static_cast<int>(s)];
}

// ---------------------------------------------------------------------------
// Naive reference: what a first XPBD implementation typically looks like.
// Array of structs (position and inverse mass interleaved, lambda inside the
// constraint), the constraint value and the gradient computed by separate
// functions (each recomputing the edge vector and its length), alpha/h^2
// recomputed per constraint. Same math and the same order as project_all, so
// after one sweep both give the same positions to round-off (checked below).
namespace naive {

struct Particle {
  Real x[3];  // m
  Real w;     // 1/kg
};

struct Edge {
  int a, b;
  Real rest;        // m
  Real compliance;  // m/N
  Real damping;     // N*s/m
  Real lambda;      // kg*m
};

Real length(const Particle* p, const Edge& e) {
  Real s = 0;
  for (int i = 0; i < 3; ++i) {
    const Real d = p[e.a].x[i] - p[e.b].x[i];
    s += d * d;
  }
  return std::sqrt(s);
}

Real constraint(const Particle* p, const Edge& e) { return length(p, e) - e.rest; }

// Gradient with respect to x_a (the one for x_b is its negative).
void gradient(const Particle* p, const Edge& e, Real g[3]) {
  const Real len = length(p, e);
  for (int i = 0; i < 3; ++i) g[i] = (p[e.a].x[i] - p[e.b].x[i]) / len;
}

void sweep(Particle* p, const Real* x_prev, Edge* edges, std::size_t n, Real h) {
  for (std::size_t k = 0; k < n; ++k) {
    Edge& e = edges[k];
    if (!(length(p, e) > kDegenerateRel * e.rest)) continue;
    const Real C = constraint(p, e);
    Real g[3];
    gradient(p, e, g);
    const Real gg = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    const Real wsum = p[e.a].w * gg + p[e.b].w * gg;
    const Real at = e.compliance / (h * h);
    const Real gamma = e.compliance * e.damping / h;
    Real gv = 0;  // grad C . (x - x_prev)
    for (int i = 0; i < 3; ++i)
      gv += g[i] * ((p[e.a].x[i] - x_prev[3 * e.a + i]) - (p[e.b].x[i] - x_prev[3 * e.b + i]));
    const Real den = (Real(1) + gamma) * wsum + at;
    if (!(den > Real(0))) continue;
    const Real dl = (-C - at * e.lambda - gamma * gv) / den;
    e.lambda += dl;
    for (int i = 0; i < 3; ++i) {
      p[e.a].x[i] += p[e.a].w * dl * g[i];
      p[e.b].x[i] -= p[e.b].w * dl * g[i];
    }
  }
}

struct Data {
  std::vector<Particle> particles;
  std::vector<Real> x_prev;  // 3 per particle
  std::vector<Edge> edges;
};

// `coloured`: the edges in schedule order (the order coloured_sweep visits
// them), else in array order.
Data from(const ClothBench& b, bool coloured = false) {
  Data d;
  for (std::size_t i = 0; i < b.sweep_x.size(); ++i) {
    d.particles.push_back(
        Particle{{b.sweep_x[i].x(), b.sweep_x[i].y(), b.sweep_x[i].z()}, b.model.inv_mass[i]});
    for (int c = 0; c < 3; ++c) d.x_prev.push_back(b.sweep_x_prev[i][c]);
  }
  for (const Distance& c : coloured ? b.model.distance_by_colour : b.model.get<Distance>())
    d.edges.push_back(Edge{c.p[0], c.p[1], c.rest, c.mat.compliance, c.mat.damping, 0});
  return d;
}

}  // namespace naive

// ---------------------------------------------------------------------------
// Kernel sweep: project_all<Distance> as step() calls it.

SolveContext context(const ClothBench& b, State& s) {
  SolveContext sc;
  sc.x = s.x.data();
  sc.x_prev = s.x_prev.data();
  sc.inv_mass = b.model.inv_mass.data();
  sc.h = b.cfg.dt / Real(b.cfg.substeps);
  sc.method = Method::xpbd;
  sc.eval.x = s.x.data();
  return sc;
}

enum class Kernel { dispatch, generic, coloured, stream, stream_avx2, stream_scalar };

bool is_stream(Kernel k) { return k == Kernel::stream || k == Kernel::stream_avx2 || k == Kernel::stream_scalar; }

using xpbd_bench::Avx2Cap;

void kernel_sweep(const ClothBench& b, State& s, const SolveContext& sc,
                  Kernel kernel = Kernel::dispatch) {
  const std::span<const Distance> cs(b.model.get<Distance>());
  std::span<Real> lambda(s.lambdas<Distance>());
  const bool damped = b.model.has_damping[type_index_v<Distance>];
  if (is_stream(kernel)) {
    project_stream(b.model, s, sc, kernel != Kernel::stream_scalar);
  } else if (kernel == Kernel::coloured) {
    const std::span<const Distance> by_colour(b.model.distance_by_colour);
    const std::span<const Index> order(b.model.distance_colours.order);
    if (damped)
      project_all_coloured<Distance, true>(by_colour, order, lambda, sc);
    else
      project_all_coloured<Distance, false>(by_colour, order, lambda, sc);
  } else if (kernel == Kernel::dispatch) {
    if (damped)
      project_all<Distance, true>(cs, lambda, sc);
    else
      project_all<Distance, false>(cs, lambda, sc);
  } else {
    if (damped)
      project_all_generic<Distance, true>(cs, lambda, sc);
    else
      project_all_generic<Distance, false>(cs, lambda, sc);
  }
}

// One sweep from the snapshot by the kernel and by the naive loop: the
// largest coordinate difference between the two, the largest correction the
// sweep applied, and the largest coordinate (all in m).
struct Agreement {
  Real diff = 0, correction = 0, scale = 0;
};

Agreement kernel_vs_naive(const ClothBench& b, Kernel kernel) {
  State s = b.snapshot;
  s.x = b.sweep_x;
  s.x_prev = b.sweep_x_prev;
  std::fill(s.lambdas<Distance>().begin(), s.lambdas<Distance>().end(), Real(0));
  const SolveContext sc = context(b, s);
  prepare_stream(b.model, s, sc.h);
  kernel_sweep(b, s, sc, kernel);
  naive::Data d = naive::from(b, kernel != Kernel::dispatch && kernel != Kernel::generic);
  naive::sweep(d.particles.data(), d.x_prev.data(), d.edges.data(), d.edges.size(),
               b.cfg.dt / Real(b.cfg.substeps));
  Agreement a;
  for (std::size_t i = 0; i < s.x.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      a.diff = std::max(a.diff, std::abs(s.x[i][c] - d.particles[i].x[c]));
      a.correction = std::max(a.correction, std::abs(s.x[i][c] - b.sweep_x[i][c]));
      a.scale = std::max(a.scale, std::abs(b.sweep_x[i][c]));
    }
  return a;
}

// Both implementations do the same floating-point operations up to
// association (d/len vs d*(1/len), alpha/h^2 vs alpha*(1/h)^2, ...), so they
// differ by a few ulp of the coordinates per projection; one Gauss-Seidel
// sweep does not amplify that much (about 1 ulp is observed). Allow 64 ulp
// of the largest coordinate. The coloured sweep is compared with the naive
// loop over the edges in schedule order. The check is only
// meaningful if the sweep's
// corrections are well above that (a wrong formula or order shows up at the
// size of the corrections), so at least 10x that is required too.
bool check_agreement(benchmark::State& bs, const ClothBench& b, Kernel kernel) {
  const Agreement a = kernel_vs_naive(b, kernel);
  const Real tol = 64 * kEpsilon * a.scale;
  std::string msg;
  if (!(a.diff <= tol))
    msg = "kernel and naive sweep disagree by " + std::to_string(a.diff) + " m";
  else if (!(a.correction > 10 * tol))
    msg = "corrections too small to compare: " + std::to_string(a.correction) + " m";
  if (!msg.empty()) {
    bs.SkipWithError(msg.c_str());
    return false;
  }
  bs.counters["max_diff_vs_naive_m"] = static_cast<double>(a.diff);
  bs.counters["max_correction_m"] = static_cast<double>(a.correction);
  return true;
}

void BM_kernel_sweep(benchmark::State& bs, Stiffness stiffness, Kernel kernel) {
  const ClothBench& b = cloth(stiffness);
  const Avx2Cap cap(kernel == Kernel::stream_avx2);
  if (!check_agreement(bs, b, kernel)) return;
  State s = b.snapshot;
  const SolveContext sc = context(b, s);
  auto& lambda = s.lambdas<Distance>();
  double ns = 0;
  for (auto _ : bs) {
    std::copy(b.sweep_x.begin(), b.sweep_x.end(), s.x.begin());  // restore (untimed)
    std::copy(b.sweep_x_prev.begin(), b.sweep_x_prev.end(), s.x_prev.begin());
    std::fill(lambda.begin(), lambda.end(), Real(0));
    if (is_stream(kernel))
      prepare_stream(b.model, s, sc.h);  // once per step in step(); zeroes the multipliers
    const auto t0 = Clock::now();
    kernel_sweep(b, s, sc, kernel);
    benchmark::ClobberMemory();
    const auto t1 = Clock::now();
    const double dt = std::chrono::duration<double>(t1 - t0).count();
    bs.SetIterationTime(dt);
    ns += dt * 1e9;
  }
  benchmark::DoNotOptimize(s.x.data());
  const double projections = double(b.model.get<Distance>().size()) * double(bs.iterations());
  bs.counters["ns_per_projection"] = ns / projections;
  bs.counters["constraints"] = double(b.model.get<Distance>().size());
  bs.counters["colours"] = double(b.model.distance_colours.num_colours());
}

void BM_naive_sweep(benchmark::State& bs, Stiffness stiffness) {
  const ClothBench& b = cloth(stiffness);
  const naive::Data start = naive::from(b);
  naive::Data d = start;
  const Real h = b.cfg.dt / Real(b.cfg.substeps);
  double ns = 0;
  for (auto _ : bs) {
    std::copy(start.particles.begin(), start.particles.end(), d.particles.begin());
    std::copy(start.edges.begin(), start.edges.end(), d.edges.begin());  // lambda = 0
    const auto t0 = Clock::now();
    naive::sweep(d.particles.data(), d.x_prev.data(), d.edges.data(), d.edges.size(), h);
    benchmark::ClobberMemory();
    const auto t1 = Clock::now();
    const double dt = std::chrono::duration<double>(t1 - t0).count();
    bs.SetIterationTime(dt);
    ns += dt * 1e9;
  }
  benchmark::DoNotOptimize(d.particles.data());
  const double projections = double(d.edges.size()) * double(bs.iterations());
  bs.counters["ns_per_projection"] = ns / projections;
  bs.counters["constraints"] = double(d.edges.size());
}

// Full step of the cloth scene; every constraint type of the model counts
// (here: the distances plus the two kinematic pins).
void BM_step(benchmark::State& bs, Stiffness stiffness, int substeps, int iterations,
             bool coloured, int threads, bool simd, bool avx2, bool levels) {
  const ClothBench& b = cloth(stiffness);
  const Avx2Cap cap(avx2);
  StepConfig cfg = b.cfg;
  cfg.coloured = coloured;
  cfg.simd = simd;
  cfg.levels = levels;
  Workers workers(threads);
  if (threads > 1) cfg.workers = &workers;
  cfg.substeps = substeps;
  cfg.iterations = iterations;
  State s = b.snapshot;
  std::size_t constraints = 0;
  for_each_constraint_type(
      [&]<class T>(std::type_identity<T>) { constraints += b.model.get<T>().size(); });
  double ns = 0;
  for (auto _ : bs) {
    s = b.snapshot;  // restore (untimed); same sizes, so the vectors reuse their storage
    const auto t0 = Clock::now();
    step(b.model, s, cfg);
    benchmark::ClobberMemory();
    const auto t1 = Clock::now();
    const double dt = std::chrono::duration<double>(t1 - t0).count();
    bs.SetIterationTime(dt);
    ns += dt * 1e9;
  }
  const double projections =
      double(constraints) * double(substeps) * double(iterations) * double(bs.iterations());
  bs.counters["ns_per_projection"] = ns / projections;
  bs.counters["constraints"] = double(constraints);
  bs.counters["ms_per_step"] = ns * 1e-6 / double(bs.iterations());
}

template <class... Args>
void add(const std::string& name, benchmark::TimeUnit unit, Args&&... args) {
  benchmark::RegisterBenchmark(name.c_str(), std::forward<Args>(args)...)
      ->UseManualTime()
      ->Unit(unit);
}

void register_all() {
  // Array-order and coloured variants registered next to each other, so
  // that with repetitions their runs are close in time.
  for (Stiffness s : {Stiffness::compliant, Stiffness::rigid, Stiffness::damped}) {
    const std::string n = name(s);
    add("naive_sweep/" + n, benchmark::kMicrosecond, BM_naive_sweep, s);
    add("generic_sweep/" + n, benchmark::kMicrosecond, BM_kernel_sweep, s, Kernel::generic);
    add("kernel_sweep/" + n, benchmark::kMicrosecond, BM_kernel_sweep, s, Kernel::dispatch);
    add("coloured_sweep/" + n, benchmark::kMicrosecond, BM_kernel_sweep, s, Kernel::coloured);
    add("stream_sweep/" + n, benchmark::kMicrosecond, BM_kernel_sweep, s, Kernel::stream);
    if (xpbd_bench::has_avx2_row())
      add("stream_avx2_sweep/" + n, benchmark::kMicrosecond, BM_kernel_sweep, s, Kernel::stream_avx2);
    add("stream_scalar_sweep/" + n, benchmark::kMicrosecond, BM_kernel_sweep, s, Kernel::stream_scalar);
  }
  for (Stiffness s : {Stiffness::compliant, Stiffness::rigid}) {
    const std::string n = name(s);
    for (auto [sub, it] : {std::pair{10, 1}, std::pair{20, 1}, std::pair{1, 10}}) {
      const std::string si = "/substeps:" + std::to_string(sub) + "/iterations:" + std::to_string(it);
      add("step/" + n + si, benchmark::kMillisecond, BM_step, s, sub, it, false, 1, true, false, false);
      add("step_levels/" + n + si, benchmark::kMillisecond, BM_step, s, sub, it, false, 1, true, false, true);
      add("step_coloured/" + n + si, benchmark::kMillisecond, BM_step, s, sub, it, true, 1, true, false, false);
      if (xpbd_bench::has_avx2_row())
        add("step_coloured_avx2/" + n + si, benchmark::kMillisecond, BM_step, s, sub, it, true, 1, true, true,
            false);
      add("step_coloured_scalar/" + n + si, benchmark::kMillisecond, BM_step, s, sub, it, true, 1, false, false,
          false);
      add("step_threads2/" + n + si, benchmark::kMillisecond, BM_step, s, sub, it, true, 2, true, false, false);
    }
  }
}

// Console output as usual, plus a summary: ns per projection of every
// benchmark (median when repetitions were asked for) and the naive sweep's
// ns per projection divided by it (the speed-up over the naive loop, with
// the same stiffness, in this run).
class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      const auto it = r.counters.find("ns_per_projection");
      if (it == r.counters.end()) continue;
      const std::string n = r.run_name.function_name;
      const bool median = r.run_type == Run::RT_Aggregate && r.aggregate_name == "median";
      if (r.run_type == Run::RT_Aggregate && !median) continue;
      Entry& e = results_[n];
      if (median || !e.median) e = Entry{it->second.value, median};
      const auto c = r.counters.find("colours");
      if (c != r.counters.end()) colours_ = c->second.value;
      if (std::find(order_.begin(), order_.end(), n) == order_.end()) order_.push_back(n);
    }
    ConsoleReporter::ReportRuns(runs);
  }

  void summary() const {
    if (results_.empty()) return;
    std::printf("\nns per projection (%s), speed-up over the naive sweep of the same\n"
                "stiffness, and for coloured and level runs the array-order run's time over\n"
                "theirs (kernel_sweep or step, same stiffness and budget), and the\n"
                "second reference's (scalar kernel; one thread) over theirs, all in this run\n",
                any_median() ? "median of repetitions" : "single run");
    const bool wide = xpbd_bench::has_avx2_row();
    std::printf("%-48s %10s %11s %11s %11s%s\n", "benchmark", "ns/proj", "naive/this", "array/this",
                "second/this", wide ? "   avx2/this" : "");
    for (const std::string& n : order_) {
      const double v = results_.at(n).value;
      // "step/rigid/substeps:10/iterations:1" -> "naive_sweep/rigid"
      const std::size_t a = n.find('/') + 1, b = n.find('/', a);
      const auto naive = results_.find("naive_sweep/" + n.substr(a, b - a));
      // "step_coloured/rigid/..." -> "step/rigid/...", "coloured_sweep/x" -> "kernel_sweep/x"
      const std::string kind = n.substr(0, a - 1), rest = n.substr(a - 1);
      std::string array, second;
      if (kind == "step_levels" || kind == "step_coloured" || kind == "step_coloured_avx2" ||
          kind == "step_coloured_scalar" || kind == "step_threads2")
        array = "step" + rest;
      if (kind == "coloured_sweep" || kind == "stream_sweep" || kind == "stream_avx2_sweep" ||
          kind == "stream_scalar_sweep")
        array = "kernel_sweep" + rest;
      std::string avx2;
      if (kind == "stream_sweep") avx2 = "stream_avx2_sweep" + rest;
      if (kind == "step_coloured") avx2 = "step_coloured_avx2" + rest;
      const auto a2 = avx2.empty() ? results_.end() : results_.find(avx2);
      if (kind == "stream_sweep") second = "stream_scalar_sweep" + rest;
      if (kind == "step_coloured") second = "step_coloured_scalar" + rest;
      if (kind == "step_threads2") second = "step_coloured" + rest;
      const auto arr = array.empty() ? results_.end() : results_.find(array);
      const auto sec = second.empty() ? results_.end() : results_.find(second);
      std::printf("%-48s %10.2f", n.c_str(), v);
      if (naive != results_.end())
        std::printf(" %11.2f", naive->second.value / v);
      else
        std::printf(" %11s", "-");
      if (arr != results_.end())
        std::printf(" %11.2f", arr->second.value / v);
      else
        std::printf(" %11s", "-");
      if (sec != results_.end())
        std::printf(" %11.2f", sec->second.value / v);
      else
        std::printf(" %11s", "-");
      if (a2 != results_.end())
        std::printf(" %11.2f\n", a2->second.value / v);
      else
        std::printf("%s\n", wide ? " -" : "");
    }
    if (colours_ > 0) std::printf("colours in the cloth's Distance schedule: %.0f\n", colours_);
    std::printf("stream kernels on this CPU: %s (Distance: %s, its levels: %s); precision: %s\n", simd_kernel(),
                distance_kernel(), distance_kernel(true), sizeof(Real) == 8 ? "double" : "float");
  }

 private:
  struct Entry {
    double value = 0;
    bool median = false;
  };
  bool any_median() const {
    for (const auto& [n, e] : results_)
      if (e.median) return true;
    return false;
  }
  std::map<std::string, Entry> results_;
  std::vector<std::string> order_;
  double colours_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  try {
    xpbd_bench::cap_from_environment();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "XPBD_BENCH_SIMD: %s\n", e.what());
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  register_all();
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.summary();
  benchmark::Shutdown();
  return 0;
}
