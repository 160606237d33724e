// Accuracy per unit time of the two Gauss-Seidel orders of the Distance
// elements (docs/bench-coloured.md, "Accuracy per unit time"): the array order
// and the coloured order (StepConfig::coloured: the stream kernel, AVX2
// where the CPU has it), on the seed's Fig. 5 cloth at 64 x 64.
//
// Scene: 64 x 64 particles, 1 m, 1 kg, flat, pinned at the two corners of
// one edge, every edge (structural, shear, bending distance) 1e-8 m/N, as
// xpbd-demo's hanging_cloth at 64 x 64. 30 frames of 1/60 s (t = 0.5 s)
// from rest. Reference: the array order at 400 substeps x 5 iterations.
// For each order and each budget (substeps x 1 iteration): the RMS and the
// largest distance of the particles from the reference at t = 0.5 s, the
// mean edge strain | |x_a - x_b| / rest - 1 |, and the median of 3 timed
// runs of the 30 frames, in ms per frame (one thread). Errors and strains
// are deterministic; compare times only within one run.
//
//   build/double/demos/bench/bench_order
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "xpbd/distance_stream.hpp"
#include "xpbd/xpbd.hpp"

namespace {

using namespace xpbd;

constexpr int kFrames = 30;

Model cloth() {
  SceneDesc scene;
  ClothGridDesc d;
  d.nx = d.ny = 64;
  d.size_u = d.size_v = 1;
  d.origin = Vec3(Real(-0.5), 0, 0);
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  d.mass = 1;
  d.stretch = d.shear_mat = d.bend_mat = Material{Real(1e-8), 0, 1};
  d.pinned = {{0, 0}, {63, 0}};
  add_cloth_grid(scene, d);
  return compile(scene);
}

struct Run {
  std::vector<Vec3> x;
  double ms_per_frame = 0;
};

Run run(const Model& m, int substeps, int iterations, bool coloured, int repeats) {
  StepConfig cfg;
  cfg.substeps = substeps;
  cfg.iterations = iterations;
  cfg.coloured = coloured;
  std::vector<double> ms;
  Run r;
  for (int k = 0; k < repeats; ++k) {
    State s = make_state(m);
    const auto t0 = std::chrono::steady_clock::now();
    for (int f = 0; f < kFrames; ++f) step(m, s, cfg);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / kFrames);
    r.x = s.x;
  }
  std::sort(ms.begin(), ms.end());
  r.ms_per_frame = ms[ms.size() / 2];
  return r;
}

double mean_strain(const Model& m, const std::vector<Vec3>& x) {
  double sum = 0;
  for (const Distance& c : m.get<Distance>())
    sum += std::abs(double((x[std::size_t(c.p[0])] - x[std::size_t(c.p[1])]).norm() / c.rest) - 1);
  return sum / double(m.get<Distance>().size());
}

}  // namespace

int main() {
  const Model m = cloth();
  const Run ref = run(m, 400, 5, false, 1);
  std::printf("64 x 64 hanging cloth, t = 0.5 s, reference: array order 400 x 5 (mean strain %.3g)\n",
              mean_strain(m, ref.x));
  std::printf("stream kernels: %s (Distance: %s); precision: %s; times: median of 3, one thread\n", simd_kernel(),
              distance_kernel(),
              sizeof(Real) == 8 ? "double" : "float");
  std::printf("%9s %9s %12s %12s %12s %12s\n", "substeps", "order", "rms_err_m", "max_err_m", "mean_strain",
              "ms_per_frame");
  for (int sub : {10, 13, 20, 26, 40, 50, 65}) {
    for (bool coloured : {false, true}) {
      const Run r = run(m, sub, 1, coloured, 3);
      double sq = 0, worst = 0;
      for (std::size_t i = 0; i < r.x.size(); ++i) {
        const double e = double((r.x[i] - ref.x[i]).norm());
        sq += e * e;
        worst = std::max(worst, e);
      }
      std::printf("%9d %9s %12.4g %12.4g %12.4g %12.3f\n", sub, coloured ? "coloured" : "array",
                  std::sqrt(sq / double(r.x.size())), worst, mean_strain(m, r.x), r.ms_per_frame);
    }
  }
  return 0;
}
