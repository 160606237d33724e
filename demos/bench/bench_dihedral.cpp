// Dihedral bending projection benchmark (docs/bench-dihedral.md,
// "bench_dihedral").
//
// Scene: a 64 x 64 cloth (1 m x 1 m, 1 kg, two corners pinned, structural
// and shear distance edges, dihedral bending of compliance 1e-3 rad^2/J,
// undamped) built with xpbd::add_cloth_grid, warmed up by 30 steps at 60 Hz
// so that it hangs folded (its hinges bent both ways); that State is the
// snapshot every timed sweep starts from (restored untimed).
//
// Each benchmark reports ns_per_hinge: the time of one Gauss-Seidel sweep
// over the 11,781 hinges (the substep h of the default 10 substeps at
// 60 Hz) divided by the hinges:
//   kernel_sweep   xpbd::project_all<DihedralBending>: the written-out kernel
//                  of solve_dihedral.hpp (what step() runs);
//   generic_sweep  project_all_generic, the eval()-based projection every
//                  type without its own kernel uses (what step() ran before);
//   coloured_sweep the kernel over the same hinges in a greedy colour order
//                  (no two hinges of a colour share a particle, colours in
//                  turn; built here as compile() builds
//                  Model::dihedral_colours): what the order alone is worth;
//   stream_sweep   xpbd::project_dihedral_stream, what step() runs with
//                  StepConfig::coloured in XPBD: the compiled hinge stream
//                  in the model's colour order with the widest kernel of
//                  this CPU (simd_kernel(): AVX-512, 8 doubles or 16
//                  floats a time, or AVX2, 4 or 8), including the copies
//                  of the particles into records and back;
//   stream_avx2_sweep  the same capped at AVX2, on a CPU with AVX-512 only;
//   stream_scalar_sweep  the same with the scalar kernel.
// The timed section is the benchmark thread's CPU time. The summary prints
// the medians and the ratio generic / kernel of this run.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "simd_cap.hpp"
#include "xpbd/dihedral_stream.hpp"
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
  std::vector<DihedralBending> by_colour;  // the hinges in greedy colour order
  int colours = 0;
  Scene() {
    SceneDesc scene;
    ClothGridDesc d;
    d.nx = d.ny = 64;
    d.pins = ClothPins::top_corners;
    d.set_bending(ClothBending::dihedral, Material{Real(1e-3), 0, 1});
    add_cloth_grid(scene, d);
    model = compile(scene);
    snapshot = make_state(model);
    StepConfig cfg;
    for (int k = 0; k < 30; ++k) step(model, snapshot, cfg);
    // Greedy colouring in array order: each hinge takes the smallest colour
    // none of its four particles has yet.
    const auto& hs = model.get<DihedralBending>();
    std::vector<std::vector<char>> used(std::size_t(model.num_particles()));
    std::vector<int> colour(hs.size());
    for (std::size_t k = 0; k < hs.size(); ++k) {
      int c = 0;
      for (;; ++c) {
        bool free = true;
        for (Index p : hs[k].p) {
          const auto& u = used[std::size_t(p)];
          if (std::size_t(c) < u.size() && u[std::size_t(c)]) free = false;
        }
        if (free) break;
      }
      colour[k] = c;
      colours = std::max(colours, c + 1);
      for (Index p : hs[k].p) {
        auto& u = used[std::size_t(p)];
        if (u.size() <= std::size_t(c)) u.resize(std::size_t(c) + 1, 0);
        u[std::size_t(c)] = 1;
      }
    }
    for (int c = 0; c < colours; ++c)
      for (std::size_t k = 0; k < hs.size(); ++k)
        if (colour[k] == c) by_colour.push_back(hs[k]);
  }
};

Scene& scene() {
  static Scene s;
  return s;
}

enum class Kind { kernel, generic, coloured, stream, stream_avx2, stream_scalar };

void BM_sweep(benchmark::State& bs, Kind kind) {
  const xpbd_bench::Avx2Cap cap(kind == Kind::stream_avx2);
  const Scene& s = scene();
  State st = s.snapshot;
  const std::span<const DihedralBending> cs(kind == Kind::coloured ? s.by_colour : s.model.get<DihedralBending>());
  std::vector<Real> lambda(cs.size(), Real(0));
  SolveContext sc;
  sc.x = st.x.data();
  sc.x_prev = st.x_prev.data();
  sc.inv_mass = s.model.inv_mass.data();
  sc.h = Real(1) / Real(600);
  sc.eval.x = st.x.data();
  const bool stream = kind == Kind::stream || kind == Kind::stream_avx2 || kind == Kind::stream_scalar;
  if (stream) prepare_stream(s.model, st, sc.h);
  double seconds = 0;
  for (auto _ : bs) {
    st.x = s.snapshot.x;  // untimed restore: same size, no allocation
    std::fill(lambda.begin(), lambda.end(), Real(0));
    std::fill(st.dihedral_lambda.begin(), st.dihedral_lambda.end(), Real(0));
    const double t0 = thread_seconds();
    if (stream)
      project_dihedral_stream(s.model, st, sc, kind != Kind::stream_scalar);
    else if (kind == Kind::generic)
      project_all_generic<DihedralBending, false>(cs, std::span<Real>(lambda), sc);
    else
      project_all<DihedralBending, false>(cs, std::span<Real>(lambda), sc);
    benchmark::ClobberMemory();
    const double dt = thread_seconds() - t0;
    bs.SetIterationTime(dt);
    seconds += dt;
  }
  bs.counters["ns_per_hinge"] = seconds * 1e9 / (double(cs.size()) * double(bs.iterations()));
  bs.counters["hinges"] = double(cs.size());
}

class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      const auto it = r.counters.find("ns_per_hinge");
      if (it == r.counters.end()) continue;
      const bool median = r.run_type == Run::RT_Aggregate && r.aggregate_name == "median";
      if (r.run_type == Run::RT_Aggregate && !median) continue;
      if (median || !results_.count(r.run_name.function_name)) results_[r.run_name.function_name] = it->second.value;
    }
    ConsoleReporter::ReportRuns(runs);
  }
  void summary() const {
    const auto k = results_.find("kernel_sweep"), g = results_.find("generic_sweep");
    const auto c = results_.find("coloured_sweep");
    if (k == results_.end() || g == results_.end()) return;
    std::printf("\nns per hinge per sweep (medians): kernel %.1f, generic %.1f; generic / kernel %.2f\n",
                k->second, g->second, g->second / k->second);
    if (c != results_.end())
      std::printf("coloured %.1f (%d colours); kernel / coloured %.2f\n", c->second, scene().colours,
                  k->second / c->second);
    const auto v = results_.find("stream_sweep"), sc = results_.find("stream_scalar_sweep");
    if (v != results_.end() && sc != results_.end())
      std::printf("stream (%s) %.1f, stream scalar %.1f; kernel / stream %.2f, stream scalar / stream %.2f\n",
                  xpbd::simd_kernel(), v->second, sc->second, k->second / v->second, sc->second / v->second);
    const auto a2 = results_.find("stream_avx2_sweep");
    if (v != results_.end() && a2 != results_.end())
      std::printf("stream capped at avx2 %.1f; avx2 / %s %.2f\n", a2->second, xpbd::simd_kernel(),
                  a2->second / v->second);
  }

 private:
  std::map<std::string, double> results_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  scene();
  benchmark::RegisterBenchmark("kernel_sweep", BM_sweep, Kind::kernel)->UseManualTime()->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("generic_sweep", BM_sweep, Kind::generic)->UseManualTime()->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("coloured_sweep", BM_sweep, Kind::coloured)->UseManualTime()->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("stream_sweep", BM_sweep, Kind::stream)->UseManualTime()->Unit(benchmark::kMicrosecond);
  if (xpbd_bench::has_avx2_row())
    benchmark::RegisterBenchmark("stream_avx2_sweep", BM_sweep, Kind::stream_avx2)
        ->UseManualTime()
        ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("stream_scalar_sweep", BM_sweep, Kind::stream_scalar)
      ->UseManualTime()
      ->Unit(benchmark::kMicrosecond);
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.summary();
  benchmark::Shutdown();
  return 0;
}
