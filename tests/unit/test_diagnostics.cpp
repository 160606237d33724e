// max_distance_strain (xpbd/diagnostics.hpp), the divergence check's
// strain without a square root or division per element, against closed
// forms (a uniformly scaled cloth) and against distance_strain's max; and
// max_distance_residual, the XPBD equation's residual over the rest length,
// against its closed form on one link and on a loaded soft link after
// stepping.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "xpbd/xpbd.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;

constexpr Real kEps = std::numeric_limits<Real>::epsilon();

// A 9 x 7 cloth of structural, shear and bending edges, 0.1 m apart.
xpbd::Model cloth() {
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc c;
  c.nx = 9;
  c.ny = 7;
  c.size_u = Real(0.8);
  c.size_v = Real(0.6);
  xpbd::add_cloth_grid(scene, c);
  return xpbd::compile(scene);
}

// Every position scaled by k about the origin: every edge is k times its
// rest length, so the strain is |k - 1| exactly (up to round-off).
TEST(MaxDistanceStrain, UniformScaleGivesItsFactor) {
  const xpbd::Model m = cloth();
  ASSERT_GT(m.get<xpbd::Distance>().size(), 100u);
  for (Real k : {Real(1), Real(1.5), Real(0.5), Real(3), Real(0.01)}) {
    xpbd::State s = xpbd::make_state(m);
    for (Vec3& x : s.x) x *= k;
    EXPECT_NEAR(xpbd::max_distance_strain(m, s), std::abs(k - 1), 16 * kEps * (1 + k)) << "scale " << k;
  }
}

// Random stretches and squeezes: the same as distance_strain's max, with
// the compact stream (compile) and without it (the elements).
TEST(MaxDistanceStrain, MatchesDistanceStrain) {
  const xpbd::Model m = cloth();
  xpbd::Model bare = m;
  bare.distance_stream = {};
  std::mt19937 rng(7);
  for (Real spread : {Real(0.001), Real(0.03), Real(0.2)}) {
    std::normal_distribution<double> n(0.0, double(spread));
    for (int trial = 0; trial < 20; ++trial) {
      xpbd::State s = xpbd::make_state(m);
      for (Vec3& x : s.x) x += Vec3(Real(n(rng)), Real(n(rng)), Real(n(rng)));
      const Real want = xpbd::distance_strain(m, s).max;
      EXPECT_NEAR(xpbd::max_distance_strain(m, s), want, 64 * kEps * (1 + want)) << "spread " << spread;
      EXPECT_NEAR(xpbd::max_distance_strain(bare, s), want, 64 * kEps * (1 + want)) << "spread " << spread;
    }
  }
}

// A compressed edge can be the largest strain: one particle moved onto its
// neighbour makes that edge's strain 1 (length 0) while the stretched
// edges on its other side stay below it.
TEST(MaxDistanceStrain, CompressionCounts) {
  const xpbd::Model m = cloth();
  xpbd::State s = xpbd::make_state(m);
  s.x[1] = s.x[0];
  EXPECT_NEAR(xpbd::max_distance_strain(m, s), 1, 16 * kEps);
  EXPECT_NEAR(xpbd::max_distance_strain(m, s), xpbd::distance_strain(m, s).max, 16 * kEps);
}

// Non-finite positions: an infinite length gives infinity, a NaN one is
// skipped as distance_strain skips it (the check's finite flag reports it).
TEST(MaxDistanceStrain, NonFiniteLengths) {
  const xpbd::Model m = cloth();
  xpbd::State s = xpbd::make_state(m);
  s.x[5].x() = Real(2) * s.x[5].x() + Real(0.02);  // some strain elsewhere
  const Real before = xpbd::max_distance_strain(m, s);
  EXPECT_GT(before, Real(0.1));
  xpbd::State nan = s;
  nan.x[40].y() = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_EQ(xpbd::max_distance_strain(m, nan), before);
  EXPECT_EQ(xpbd::distance_strain(m, nan).max, xpbd::distance_strain(m, s).max);
  xpbd::State inf = s;
  inf.x[40].y() = std::numeric_limits<Real>::infinity();
  EXPECT_EQ(xpbd::max_distance_strain(m, inf), std::numeric_limits<Real>::infinity());
  EXPECT_EQ(xpbd::distance_strain(m, inf).max, std::numeric_limits<Real>::infinity());
}

TEST(MaxDistanceStrain, NoDistanceElementsGiveZero) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3::Zero(), Real(1));
  const xpbd::Model m = xpbd::compile(scene);
  EXPECT_EQ(xpbd::max_distance_strain(m, xpbd::make_state(m)), Real(0));
}

// One link of rest length 1 from a pinned particle to one of mass 1,
// at compliance alpha (m/N) and damping beta (N s/m).
xpbd::Model link(Real alpha, Real beta) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3::Zero(), Real(0));
  scene.add_particle(Vec3(0, -1, 0), Real(1));
  xpbd::Material mat;
  mat.compliance = alpha;
  mat.damping = beta;
  scene.distances.push_back(xpbd::DistanceDesc{0, 1, Real(1), mat});
  return xpbd::compile(scene);
}

// The link stretched by C = 0.3, at h = 1e-3 s: |C + at lambda + gamma
// n.(dx_a - dx_b)| / rest, term by term.
TEST(MaxDistanceResidual, IsTheXpbdEquationsResidualOnOneLink) {
  const Real alpha = Real(1e-4), beta = Real(2), h = Real(1e-3), C = Real(0.3);
  const Real at = alpha / (h * h), gamma = alpha * beta / h;
  const xpbd::Model m = link(alpha, beta);
  xpbd::State s = xpbd::make_state(m);
  s.x[1] = Vec3(0, -(1 + C), 0);
  s.x_prev = s.x;  // not moving: no damping term
  s.last_substep = h;
  auto& lambda = s.lambdas<xpbd::Distance>();
  lambda[0] = -C / at;  // the compliance's own stretch: converged
  EXPECT_NEAR(xpbd::max_distance_residual(m, s), 0, 16 * kEps);
  EXPECT_NEAR(xpbd::max_distance_strain(m, s), C, 16 * kEps);
  lambda[0] = -C / (2 * at);  // half the force: half the stretch unexplained
  EXPECT_NEAR(xpbd::max_distance_residual(m, s), C / 2, 16 * kEps);
  lambda[0] = 0;
  EXPECT_NEAR(xpbd::max_distance_residual(m, s), C, 16 * kEps);
  // Particle 1 moved down by 0.01 in the substep: n = (x_0 - x_1) / len is
  // +y and (x_0 - x_prev_0) - (x_1 - x_prev_1) = +0.01 y.
  lambda[0] = -C / at;
  s.x_prev[1] = s.x[1] + Vec3(0, Real(0.01), 0);
  EXPECT_NEAR(xpbd::max_distance_residual(m, s), gamma * Real(0.01), 64 * kEps);
  // Compliance 0: the strain, whatever the multiplier.
  const xpbd::Model stiff = link(0, beta);
  EXPECT_NEAR(xpbd::max_distance_residual(stiff, s), C, 16 * kEps);
  // Before any step (h = 0): the strain.
  s.last_substep = 0;
  EXPECT_NEAR(xpbd::max_distance_residual(m, s), C, 16 * kEps);
}

// A 1 kg mass on a soft link (alpha = 0.03 m/N) starts at rest at its
// static stretch alpha m g = 0.2943 m and is stepped at 10 substeps: the
// strain stays the static stretch (closed form) and the residual is about
// 0, where at compliance 0 the residual is the strain itself.
TEST(MaxDistanceResidual, ASoftLinkAtRestUnderLoadHasNoResidual) {
  const Real g = Real(9.81), alpha = Real(0.03), stretch = alpha * g;
  const xpbd::Model m = link(alpha, 0);
  xpbd::State s = xpbd::make_state(m);
  s.x[1] = Vec3(0, -(1 + stretch), 0);
  xpbd::StepConfig cfg;
  cfg.dt = Real(1) / Real(60);
  cfg.substeps = 10;
  cfg.gravity = Vec3(0, -g, 0);
  for (int k = 0; k < 60; ++k) xpbd::step(m, s, cfg);
  EXPECT_NEAR(xpbd::max_distance_strain(m, s), stretch, Real(1e-6));
  EXPECT_LT(xpbd::max_distance_residual(m, s), Real(1e-6));
  // A stiff chain (compliance 0: pinned, 1 kg, 1 kg) stretched and
  // stepped once: the sweep leaves the first link stretched after the
  // second moved their shared particle, and no force explains it, so the
  // residual is the strain.
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3::Zero(), Real(0));
  scene.add_particle(Vec3(0, -1, 0), Real(1));
  scene.add_particle(Vec3(0, -2, 0), Real(1));
  scene.distances.push_back(xpbd::DistanceDesc{0, 1, Real(1), {}});
  scene.distances.push_back(xpbd::DistanceDesc{1, 2, Real(1), {}});
  const xpbd::Model stiff = xpbd::compile(scene);
  xpbd::State t = xpbd::make_state(stiff);
  t.x[1] = Vec3(0, Real(-1.5), 0);
  t.x[2] = Vec3(0, Real(-3), 0);
  cfg.substeps = 1;
  xpbd::step(stiff, t, cfg);
  const Real strain = xpbd::distance_strain(stiff, t).max;
  EXPECT_GT(strain, Real(0.1));
  EXPECT_NEAR(xpbd::max_distance_residual(stiff, t), strain, 16 * kEps);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
