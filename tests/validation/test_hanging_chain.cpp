// Vertical hanging chain (docs/design.md section 6, row 4): N = 20 particles of
// 1 kg, spacing l = 0.01 m, g = 10 m/s^2, particle 0 pinned and kinematic.
//
// Indexing. add_rope gives particle 0 (the pinned top) mass 0, so N - 1 = 19
// particles of mass m hang, and link k joins particles k and k+1
// (k = 0..N-2). Link k holds up particles k+1..N-1, i.e. N-1-k of them, so
// its tension is (N-1-k) m g: 190 N in link 0 (the support), 10 N in the last
// link (the same 0-based form as docs/design.md section 6).
//
// Force estimate. At rest, each substep's prediction moves every hanging
// particle h^2 g down, and the projections must move it back. Summing the
// position updates of particle i over the iterations gives
//   sum_k w_i lambda_k grad_i C_k = -h^2 g,
// so at steady state the accumulated lambda_k/h^2 satisfy force balance at
// every particle exactly, whether or not the iterations converged; in a chain
// force balance fixes every tension. The estimate lambda/h^2 is then exact up
// to round-off and the residual motion left from the start, which the test
// lets decay (drag) before measuring.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

constexpr int N = 20;
constexpr Real m = 1, g = 10, l = Real(0.01);

// The chain: N particles l apart hanging down from (0, 1, 0), the first pinned.
Model chain_model(const Material& mat) {
  SceneDesc sd;
  RopeDesc rope;
  rope.n = N;
  rope.start = Vec3(0, 1, 0);
  rope.dir = -Vec3::UnitY();
  rope.spacing = l;
  rope.mass = m;
  rope.pin_first = true;
  rope.mat = mat;
  add_rope(sd, rope);
  return compile(sd);
}

void check_chain(const Material& mat, int substeps, int iterations) {
  const Model model = chain_model(mat);
  ASSERT_EQ(model.get<Distance>().size(), std::size_t(N - 1));
  ASSERT_EQ(total_mass(model), (N - 1) * m);
  State s = make_state(model);
  StepConfig cfg;
  cfg.substeps = substeps;
  cfg.iterations = iterations;
  cfg.gravity = Vec3(0, -g, 0);
  cfg.drag = 5;  // 1/s: lets the start-up transient decay; no effect at rest
  for (int n = 0; n < 600; ++n) step(model, s, cfg);
  ASSERT_TRUE(test::all_finite(s));

  // Support force: link 0, tension (negative force = pulls the particles
  // together, see constraint_force).
  const Real support = -constraint_force<Distance>(s, 0);
  std::printf("chain (alpha=%g, %d substeps, %d iterations): support %.6f N\n",
              double(mat.compliance), substeps, iterations, double(support));
  EXPECT_NEAR(support, (N - 1) * m * g, 1e-3 * (N - 1) * m * g);
  for (int k = 0; k < N - 1; ++k) {
    const Real expected = Real(N - 1 - k) * m * g;
    EXPECT_NEAR(-constraint_force<Distance>(s, std::size_t(k)), expected, 1e-3 * expected)
        << "link " << k;
    // The force vector on the lower particle of the link points up.
    const Vec3 f = constraint_force_on<Distance>(model, s, std::size_t(k), 1);
    EXPECT_NEAR(f.y(), expected, 1e-3 * expected) << "link " << k;
  }
  // The kinematic pin does no work: its particle has inverse mass 0.
  EXPECT_EQ(s.x[0], Vec3(0, 1, 0));
}

TEST(HangingChain, SupportForceFromLambdaStiff) {
  check_chain(Material{0, 0, 1}, 10, 20);
}

// A compliant chain: link k also stretches by alpha (N-1-k) m g.
TEST(HangingChain, SupportForceFromLambdaCompliant) {
  check_chain(Material{Real(1e-6), 0, 1}, 10, 20);
}

// The deformation, not only the force: at alpha = 1e-8 m/N one sweep per
// substep leaves the chain far longer than its compliance says (docs/design.md
// section 8: 260 times at 10 x 1); with the direct solve along the chain
// (StepConfig::direct_chains) every link stretches by alpha times the weight
// below it. Returns the largest |stretch - alpha F| over the links (m).
Real stretch_error(bool direct, Real& top_stretch) {
  constexpr Real alpha = Real(1e-8);
  const Model model = chain_model(Material{alpha, 0, 1});
  State s = make_state(model);
  StepConfig cfg;
  cfg.gravity = Vec3(0, -g, 0);
  cfg.drag = 5;  // 1/s: lets the start-up transient decay
  cfg.direct_chains = direct;
  for (int n = 0; n < 600; ++n) step(model, s, cfg);
  EXPECT_TRUE(test::all_finite(s));
  Real worst = 0;
  for (int k = 0; k < N - 1; ++k) {
    const Real stretch = (s.x[std::size_t(k + 1)] - s.x[std::size_t(k)]).norm() - l;
    if (k == 0) top_stretch = stretch;
    worst = std::max(worst, std::abs(stretch - alpha * Real(N - 1 - k) * m * g));
  }
  return worst;
}

TEST(HangingChain, DirectSolveStretchesEachLinkByItsCompliance) {
  Real top_swept = 0, top_direct = 0;
  const Real swept = stretch_error(false, top_swept);
  const Real direct = stretch_error(true, top_direct);
  std::printf("chain (alpha=1e-8, 10 x 1): top link stretch %.4g m swept, %.4g m direct (alpha F = 1.9e-6 m); "
              "largest error %.3g m, %.3g m\n",
              double(top_swept), double(top_direct), double(swept), double(direct));
  // The top link carries 190 N: alpha F = 1.9e-6 m. Positions near 1 m are
  // spaced 2.2e-16 m in double and 6e-8 m in float.
  const Real round_off = sizeof(Real) == 8 ? Real(1e-12) : Real(3e-7);
  EXPECT_GT(swept, Real(10 * 1.9e-6));
  EXPECT_LT(direct, round_off);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
