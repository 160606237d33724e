// Tether projection benchmark (docs/bench-tethers.md, "bench_tethers").
//
// Scene: a 64 x 64 cloth (1 m x 1 m, 1 kg, two corners pinned, structural,
// shear and bending distance edges as the builder's defaults, rigid) with a
// tether from every movable particle to each pin (8,188 tethers, euclidean
// lengths), built with xpbd::add_cloth_grid and warmed up by 30 steps at 60
// Hz so that it hangs (part of the tethers taut); that State is the
// snapshot every timed run starts from (restored untimed).
//
// Sweeps, reported as ns_per_tether (one Gauss-Seidel sweep over the
// tethers at the substep of 10 substeps at 60 Hz, over the tethers):
//   array_sweep          xpbd::project_all<Tether>: the pair-distance kernel
//                        in array order (what step() runs without
//                        StepConfig::coloured);
//   stream_sweep         xpbd::project_tether_stream: the compiled stream in
//                        Model::tether_colours order with the widest kernel
//                        of this CPU (what step() runs with coloured in
//                        XPBD), including the copies of the particles into
//                        records and back;
//   stream_avx2_sweep    the same capped at AVX2, on a CPU with AVX-512
//                        only;
//   stream_scalar_sweep  the same with the scalar kernel.
// Steps, reported as ms_per_step (20 substeps x 1 iteration, the whole
// cloth: edges and tethers): step_array (element by element,
// StepConfig::levels off), step_levels (the same over array order's levels
// of both types, the default: the same bits) and step_coloured.
// The timed section is the benchmark thread's CPU time. The summary prints
// the medians and the ratios of this run.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "simd_cap.hpp"
#include "xpbd/distance_stream.hpp"
#include "xpbd/solve.hpp"
#include "xpbd/xpbd.hpp"

namespace {

using namespace xpbd;

double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

struct Scene {
  Model model;
  State snapshot;
  Scene() {
    SceneDesc scene;
    ClothGridDesc d;
    d.nx = d.ny = 64;
    d.pins = ClothPins::top_corners;
    d.tethers = TetherAnchors::all_pinned;
    d.tether_metric = TetherMetric::euclidean;
    add_cloth_grid(scene, d);
    model = compile(scene);
    snapshot = make_state(model);
    StepConfig cfg;
    for (int k = 0; k < 30; ++k) step(model, snapshot, cfg);
  }
};

Scene& scene() {
  static Scene s;
  return s;
}

enum class Kind { array, stream, stream_avx2, stream_scalar };

void BM_sweep(benchmark::State& bs, Kind kind) {
  const xpbd_bench::Avx2Cap cap(kind == Kind::stream_avx2);
  const Scene& s = scene();
  State st = s.snapshot;
  const std::span<const Tether> cs(s.model.get<Tether>());
  std::vector<Real> lambda(cs.size(), Real(0));
  SolveContext sc;
  sc.x = st.x.data();
  sc.x_prev = st.x_prev.data();
  sc.inv_mass = s.model.inv_mass.data();
  sc.h = Real(1) / Real(600);
  sc.eval.x = st.x.data();
  if (kind != Kind::array) prepare_stream(s.model, st, sc.h);
  double seconds = 0;
  for (auto _ : bs) {
    st.x = s.snapshot.x;  // untimed restore: same size, no allocation
    std::fill(lambda.begin(), lambda.end(), Real(0));
    std::fill(st.tether_lambda.begin(), st.tether_lambda.end(), Real(0));
    const double t0 = thread_seconds();
    if (kind == Kind::array)
      project_all<Tether, false>(cs, std::span<Real>(lambda), sc);
    else
      project_tether_stream(s.model, st, sc, kind != Kind::stream_scalar);
    benchmark::ClobberMemory();
    const double dt = thread_seconds() - t0;
    bs.SetIterationTime(dt);
    seconds += dt;
  }
  bs.counters["ns_per_tether"] = seconds * 1e9 / (double(cs.size()) * double(bs.iterations()));
  bs.counters["tethers"] = double(cs.size());
}

void BM_step(benchmark::State& bs, bool coloured, bool levels) {
  const Scene& s = scene();
  State st = s.snapshot;
  StepConfig cfg;
  cfg.substeps = 20;
  cfg.coloured = coloured;
  cfg.levels = levels;
  double seconds = 0;
  for (auto _ : bs) {
    st = s.snapshot;  // untimed restore
    const double t0 = thread_seconds();
    step(s.model, st, cfg);
    benchmark::ClobberMemory();
    const double dt = thread_seconds() - t0;
    bs.SetIterationTime(dt);
    seconds += dt;
  }
  bs.counters["ms_per_step"] = seconds * 1e3 / double(bs.iterations());
}

class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      const bool median = r.run_type == Run::RT_Aggregate && r.aggregate_name == "median";
      if (r.run_type == Run::RT_Aggregate && !median) continue;
      for (const char* c : {"ns_per_tether", "ms_per_step"}) {
        const auto it = r.counters.find(c);
        if (it == r.counters.end()) continue;
        if (median || !results_.count(r.run_name.function_name)) results_[r.run_name.function_name] = it->second.value;
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }
  void summary() const {
    const auto a = results_.find("array_sweep"), v = results_.find("stream_sweep");
    const auto sc = results_.find("stream_scalar_sweep");
    if (a != results_.end() && v != results_.end() && sc != results_.end())
      std::printf("\nns per tether per sweep (medians): array %.2f, stream (%s) %.2f, stream scalar %.2f; "
                  "array / stream %.2f, stream scalar / stream %.2f\n",
                  a->second, xpbd::simd_kernel(), v->second, sc->second, a->second / v->second,
                  sc->second / v->second);
    const auto a2 = results_.find("stream_avx2_sweep");
    if (v != results_.end() && a2 != results_.end())
      std::printf("stream capped at avx2 %.2f; avx2 / %s %.2f\n", a2->second, xpbd::simd_kernel(),
                  a2->second / v->second);
    const auto sa = results_.find("step_array"), sv = results_.find("step_coloured");
    const auto sl = results_.find("step_levels");
    if (sa != results_.end() && sv != results_.end() && sl != results_.end())
      std::printf("ms per step, 20 x 1 (medians): array %.3f, levels %.3f, coloured %.3f; array / levels %.2f, "
                  "array / coloured %.2f\n",
                  sa->second, sl->second, sv->second, sa->second / sl->second, sa->second / sv->second);
  }

 private:
  std::map<std::string, double> results_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  scene();
  benchmark::RegisterBenchmark("array_sweep", BM_sweep, Kind::array)->UseManualTime()->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("stream_sweep", BM_sweep, Kind::stream)->UseManualTime()->Unit(benchmark::kMicrosecond);
  if (xpbd_bench::has_avx2_row())
    benchmark::RegisterBenchmark("stream_avx2_sweep", BM_sweep, Kind::stream_avx2)
        ->UseManualTime()
        ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("stream_scalar_sweep", BM_sweep, Kind::stream_scalar)
      ->UseManualTime()
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("step_array", BM_step, false, false)->UseManualTime()->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("step_levels", BM_step, false, true)->UseManualTime()->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("step_coloured", BM_step, true, false)->UseManualTime()->Unit(benchmark::kMillisecond);
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.summary();
  benchmark::Shutdown();
  return 0;
}
