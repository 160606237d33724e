// max_distance_strain (xpbd/diagnostics.hpp), the divergence check's
// strain without a square root or division per element, against closed
// forms (a uniformly scaled cloth) and against distance_strain's max.
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

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
