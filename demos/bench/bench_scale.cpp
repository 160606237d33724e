// Cost against size: the coloured XPBD step on cloths from 32 x 32 to
// 1024 x 1024 particles, at 1 and 2 threads, and the cost of one barrier of
// the thread pool (docs/bench-threads.md, "bench_scale").
//
// Scene: an N x N cloth (1 m x 1 m, 1 kg, horizontal, two corners pinned,
// structural + shear + bending-distance edges, compliances 1e-6 / 1e-5 /
// 1e-4 m/N as bench_distance's compliant cloth), warmed up by 3 steps of
// free fall. Each timed step starts from that snapshot. Budget: 20
// substeps x 1 iteration of 1/60 s.
//
//   step_array/N     step() in array order, element by element
//                    (StepConfig::levels off), one thread;
//   step_levels/N    the same step over array order's levels with the
//                    vector kernel (the default; the same bits), one thread;
//   step_coloured/N  step() with StepConfig::coloured (the stream kernel);
//   step_threads2/N  the same with StepConfig::workers of 2 threads (wall time);
//   barrier/T        one Workers::run of T tasks that do nothing: what a
//                    colour pays for being split, besides its work.
// Every step benchmark reports ns per particle per substep and ns per
// distance projection. At the end the program prints a table per size:
// those figures, the array-order step's time over the coloured one's and
// the one-thread coloured step's over the two-thread one's, all in this
// run; then where the time of the one-thread coloured step goes: the share
// of each stage of step() (StepConfig::times, profile.hpp) over 3 steps
// per size. XPBD_BENCH_SIMD=avx2 (or scalar) in the environment caps the
// stream kernels for the whole run (simd_cap.hpp).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "simd_cap.hpp"
#include "xpbd/distance_stream.hpp"
#include "xpbd/workers.hpp"
#include "xpbd/xpbd.hpp"

namespace {

using namespace xpbd;
using Clock = std::chrono::steady_clock;

constexpr int kSubsteps = 20;
constexpr int kSizes[] = {32, 64, 128, 256, 512, 1024};

struct Cloth {
  Model model;
  State snapshot;
};

std::unique_ptr<Cloth> build(int n) {
  SceneDesc scene;
  ClothGridDesc d;
  d.nx = d.ny = n;
  d.size_u = d.size_v = 1;
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  d.mass = 1;
  d.pinned = {{0, 0}, {n - 1, 0}};
  d.stretch.compliance = Real(1e-6);
  d.shear_mat.compliance = Real(1e-5);
  d.bend_mat.compliance = Real(1e-4);
  add_cloth_grid(scene, d);
  auto c = std::make_unique<Cloth>();
  c->model = compile(scene);
  State s = make_state(c->model);
  StepConfig cfg;
  cfg.substeps = kSubsteps;
  cfg.coloured = true;
  for (int i = 0; i < 3; ++i) step(c->model, s, cfg);
  c->snapshot = std::move(s);
  return c;
}

// Built on first use, one size at a time (the 1024 x 1024 cloth holds
// about 1 GB); the previous size is freed first.
const Cloth& cloth(int n) {
  static int built = 0;
  static std::unique_ptr<Cloth> c;
  if (built != n) {
    c.reset();
    c = build(n);
    built = n;
  }
  return *c;
}

enum class Kind { array, levels, coloured, threads2 };

void BM_step(benchmark::State& bs, int n, Kind kind) {
  const Cloth& c = cloth(n);
  StepConfig cfg;
  cfg.substeps = kSubsteps;
  cfg.coloured = kind == Kind::coloured || kind == Kind::threads2;
  cfg.levels = kind == Kind::levels;
  Workers w(kind == Kind::threads2 ? 2 : 1);
  if (kind == Kind::threads2) cfg.workers = &w;
  State s = c.snapshot;
  double ns = 0;
  for (auto _ : bs) {
    s = c.snapshot;  // restore (untimed)
    const auto t0 = Clock::now();
    step(c.model, s, cfg);
    benchmark::ClobberMemory();
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    bs.SetIterationTime(dt);
    ns += dt * 1e9;
  }
  const double steps = double(bs.iterations());
  bs.counters["ns_per_particle_substep"] = ns / (steps * kSubsteps * double(c.model.num_particles()));
  bs.counters["ns_per_projection"] = ns / (steps * kSubsteps * double(c.model.get<Distance>().size()));
  bs.counters["ms_per_step"] = ns * 1e-6 / steps;
  bs.counters["colours"] = double(c.model.distance_colours.num_colours());
}

void BM_barrier(benchmark::State& bs, int tasks) {
  Workers w(2);
  auto nothing = [](int) {};
  double ns = 0;
  for (auto _ : bs) {
    const auto t0 = Clock::now();
    w.run(tasks, nothing);
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    bs.SetIterationTime(dt);
    ns += dt * 1e9;
  }
  bs.counters["ns_per_run"] = ns / double(bs.iterations());
}

// Console output, plus the per-size table.
class Summary : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      const bool median = r.run_type == Run::RT_Aggregate && r.aggregate_name == "median";
      if (r.run_type == Run::RT_Aggregate && !median) continue;
      const std::string name = r.run_name.function_name;
      for (const char* k : {"ns_per_particle_substep", "ns_per_projection", "ms_per_step", "ns_per_run"}) {
        const auto it = r.counters.find(k);
        if (it != r.counters.end() && (median || !medians_.count(name))) values_[name][k] = it->second.value;
      }
      if (median) medians_[name] = true;
    }
    ConsoleReporter::ReportRuns(runs);
  }

  void summary() const {
    std::printf("\n%s; ns per particle per substep and per distance projection, %d substeps x 1,\n"
                "stream kernels: %s (Distance: %s, its levels: %s), precision: %s; ratios measured in this run\n",
                medians_.empty() ? "single runs" : "medians of repetitions", kSubsteps, simd_kernel(), distance_kernel(),
                distance_kernel(true), sizeof(Real) == 8 ? "double" : "float");
    std::printf("%6s %11s %11s %11s %11s %11s %11s %13s %13s %13s\n", "N", "array/p", "lev/p", "col/p", "col2/p",
                "col/proj", "col2/proj", "array/lev", "array/col", "col/col2");
    for (int n : kSizes) {
      auto find = [&](const char* kind) {
        std::string key(kind);
        key += std::to_string(n);
        return values_.find(key);
      };
      const auto a = find("step_array/"), l = find("step_levels/"), c = find("step_coloured/"),
                 t = find("step_threads2/");
      if (a == values_.end() || l == values_.end() || c == values_.end() || t == values_.end()) continue;
      auto v = [](const auto& it, const char* k) { return it->second.at(k); };
      std::printf("%6d %11.2f %11.2f %11.2f %11.2f %11.2f %11.2f %13.2f %13.2f %13.2f\n", n,
                  v(a, "ns_per_particle_substep"), v(l, "ns_per_particle_substep"), v(c, "ns_per_particle_substep"),
                  v(t, "ns_per_particle_substep"), v(c, "ns_per_projection"), v(t, "ns_per_projection"),
                  v(a, "ms_per_step") / v(l, "ms_per_step"), v(a, "ms_per_step") / v(c, "ms_per_step"),
                  v(c, "ms_per_step") / v(t, "ms_per_step"));
    }
    for (const auto& [name, vals] : values_)
      if (vals.count("ns_per_run")) std::printf("%s: %.0f ns per run\n", name.c_str(), vals.at("ns_per_run"));
  }

 private:
  std::map<std::string, std::map<std::string, double>> values_;
  std::map<std::string, bool> medians_;
};

// Stage shares of the one-thread coloured step per size (StageTimes).
void print_stages() {
  std::printf("\nwhere the time goes, coloured step on one thread (%% of the timed stages, 3 steps):\n");
  std::vector<std::size_t> shown;
  std::vector<std::pair<int, StageTimes>> rows;
  for (int n : kSizes) {
    const Cloth& c = cloth(n);
    StageTimes t;
    StepConfig cfg;
    cfg.substeps = kSubsteps;
    cfg.coloured = true;
    cfg.times = &t;
    State s = c.snapshot;
    for (int k = 0; k < 3; ++k) step(c.model, s, cfg);
    for (std::size_t k = 0; k < stage::count; ++k)
      if (t.calls[k] > 0 && std::find(shown.begin(), shown.end(), k) == shown.end()) shown.push_back(k);
    rows.emplace_back(n, t);
  }
  std::printf("%6s", "N");
  for (std::size_t k : shown) std::printf(" %16s", stage_name(k));
  std::printf(" %12s\n", "ms/step");
  for (const auto& [n, t] : rows) {
    double total = 0;
    for (std::size_t k : shown) total += double(t.ns[k]);
    std::printf("%6d", n);
    for (std::size_t k : shown) std::printf(" %15.1f%%", 100.0 * double(t.ns[k]) / total);
    std::printf(" %12.2f\n", total * 1e-6 / 3);
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    xpbd_bench::cap_from_environment();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "XPBD_BENCH_SIMD: %s\n", e.what());
    return 2;
  }
  for (int tasks : {1, 2, 4}) {
    benchmark::RegisterBenchmark(("barrier/" + std::to_string(tasks)).c_str(), BM_barrier, tasks)
        ->UseManualTime()
        ->Unit(benchmark::kMicrosecond);
  }
  for (int n : kSizes) {
    // Few iterations for the large cloths (a 1024 x 1024 step takes about a second).
    const int iterations = n >= 512 ? 3 : 0;
    for (auto [kind, name] :
         {std::pair{Kind::array, "step_array/"}, std::pair{Kind::levels, "step_levels/"},
          std::pair{Kind::coloured, "step_coloured/"}, std::pair{Kind::threads2, "step_threads2/"}}) {
      auto* b = benchmark::RegisterBenchmark((std::string(name) + std::to_string(n)).c_str(), BM_step, n, kind);
      b->UseManualTime()->Unit(benchmark::kMillisecond);
      if (iterations > 0) b->Iterations(iterations);
    }
  }
  benchmark::Initialize(&argc, argv);
  Summary reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.summary();
  print_stages();
  benchmark::Shutdown();
  return 0;
}
