// The prediction's AVX-512 kernel (xpbd/src/predict_avx512.cpp) against the
// scalar loop (step.cpp, predict_range): step() with StepConfig::simd on and
// off, and with the kernel capped at AVX2 (which runs the scalar
// prediction), must give the same bits. The scene exercises each path of
// the kernel: a particle count that leaves a partial batch (1 + 46 x 45 =
// 2071 = 129 x 16 + 7 = 258 x 8 + 7), kinematic particles with and without
// a pin, external forces, damped streams (the records of the substep's
// start), drag, a shorter step after longer ones (the blended velocity
// update), the array order and the coloured one, and two threads (the
// particle passes are split from 2 x 1024 particles on, stream.hpp; the
// second range starts at particle 1035, inside a batch).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "support/xpbd_test.hpp"
#include "xpbd/workers.hpp"
#include "xpbd/xpbd.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd;

struct Outcome {
  std::vector<Vec3> x, v;
  Real moved = 0;  // m, the largest distance of a particle from where it started
};

Outcome run(bool damped, bool coloured, bool simd, int threads) {
  SceneDesc scene;
  ClothGridDesc d;
  d.nx = 46;
  d.ny = 45;
  d.size_u = d.size_v = 1;
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  d.mass = 1;
  d.pinned = {{0, 0}, {45, 0}};
  d.stretch.compliance = Real(1e-6);
  d.shear_mat.compliance = Real(1e-5);
  d.bend_mat.compliance = Real(1e-4);
  if (damped) d.stretch.damping = d.shear_mat.damping = d.bend_mat.damping = Real(10);
  // A kinematic particle without a pin, moving at constant velocity: the
  // prediction alone moves it (a pinned one is put on its target after).
  // Particle 0, in the first batch.
  scene.add_particle(Vec3(0.5, 0.5, 0.5), 0, 0, Vec3(0.3, -0.2, 0.1));
  add_cloth_grid(scene, d);
  const Model m = compile(scene);
  State s = make_state(m);
  std::mt19937 rng(5);
  std::uniform_real_distribution<Real> u(Real(-1), Real(1));
  s.f_ext.resize(s.x.size());
  for (Vec3& f : s.f_ext) f = Vec3(u(rng), u(rng), u(rng));  // N
  StepConfig cfg;
  cfg.substeps = 5;
  cfg.coloured = coloured;
  cfg.simd = simd;
  cfg.drag = Real(0.2);
  Workers w(threads);
  if (threads > 1) cfg.workers = &w;
  for (int k = 0; k < 24; ++k) {
    cfg.dt = k % 8 == 7 ? Real(1) / Real(240) : Real(1) / Real(60);  // a shorter step: blended velocities
    step(m, s, cfg);
  }
  Real moved = 0;
  for (std::size_t i = 0; i < s.x.size(); ++i) moved = std::max(moved, (s.x[i] - m.x0[i]).norm());
  return {s.x, s.v, moved};
}

TEST(PredictKernel, VectorAndScalarGiveTheSameBits) {
  if (test::vector_kernels().empty() || test::vector_kernels()[0] != "avx512")
    GTEST_SKIP() << "the prediction's vector kernel is AVX-512; this CPU has " << simd_kernel();
  for (bool damped : {false, true})
    for (bool coloured : {false, true})
      for (int threads : {1, 2}) {
        if (threads > 1 && !coloured) continue;  // the workers split the coloured sweep only
        const Outcome vec = run(damped, coloured, true, threads);
        const Outcome scalar = run(damped, coloured, false, threads);
        Outcome capped;
        {
          const test::KernelCap cap("avx2");  // the scalar prediction, the AVX2 sweep
          capped = run(damped, coloured, true, threads);
        }
        for (std::size_t i = 0; i < vec.x.size(); ++i) {
          ASSERT_EQ(vec.x[i], scalar.x[i]) << "particle " << i << " damped " << damped << " coloured " << coloured
                                           << " threads " << threads;
          ASSERT_EQ(vec.v[i], scalar.v[i]) << "particle " << i;
          ASSERT_EQ(vec.x[i], capped.x[i]) << "particle " << i;
          ASSERT_EQ(vec.v[i], capped.v[i]) << "particle " << i;
        }
        EXPECT_GT(vec.moved, Real(0.05)) << "the cloth did not move";
      }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
