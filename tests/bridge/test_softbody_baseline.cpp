// The btSoftBody baseline (bullet_bridge/src/softbody_baseline.cpp) against
// closed-form and independently computed references: it must build the scene
// it is given (nodes, links, masses, rest lengths) and Bullet must then do what
// its integrator and link projection say it does.
#include <gtest/gtest.h>

#include <BulletSoftBody/btSoftBody.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "xpbd/builders.hpp"
#include "xpbd/error.hpp"
#include "xpbd/scene.hpp"
#include "xpbd_bullet/softbody_baseline.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;
using xpbd_bullet::SoftBodyBaseline;
using xpbd_bullet::SoftBodyBaselineConfig;

constexpr Real kEps = std::numeric_limits<btScalar>::epsilon();

// The internal step as btSoftBody sees it: btSoftRigidDynamicsWorld calls
// m_softBodySolver->predictMotion(float(timeStep)), so in a double build the
// soft body integrates with the step rounded to float. (Identity in a float build.)
Real bullet_soft_step(Real h) { return static_cast<Real>(static_cast<float>(h)); }

// ---------------------------------------------------------------------------
// Topology, masses and rest lengths are those of the SceneDesc.

TEST(SoftBodyBaseline, MatchesSceneNodeCountLinkCountMassesAndRestLengths) {
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc c;
  c.nx = 7;
  c.ny = 5;
  c.size_u = Real(0.6);
  c.size_v = Real(0.4);
  c.mass = Real(0.8);
  c.origin = Vec3(Real(-0.3), Real(1), Real(0));
  c.u = Vec3::UnitX();
  c.v = Vec3::UnitZ();
  c.pinned = {{0, 0}, {6, 0}};
  const xpbd::ClothGrid g = xpbd::add_cloth_grid(scene, c);

  SoftBodyBaselineConfig cfg;
  cfg.internal_steps = 3;
  cfg.piterations = 7;
  SoftBodyBaseline sb(scene, cfg);
  const btSoftBody& b = sb.body();

  // Counted from the grid, not from the builder: structural (nx-1)ny + nx(ny-1),
  // shear 2(nx-1)(ny-1), bending-distance (nx-2)ny + nx(ny-2).
  const int nx = c.nx, ny = c.ny;
  const int links = (nx - 1) * ny + nx * (ny - 1) + 2 * (nx - 1) * (ny - 1) + (nx - 2) * ny +
                    nx * (ny - 2);
  EXPECT_EQ(sb.num_nodes(), nx * ny);
  EXPECT_EQ(sb.num_links(), links);
  ASSERT_EQ(sb.num_links(), static_cast<int>(scene.distances.size()));
  EXPECT_EQ(sb.projections_per_frame(), 3LL * 7LL * links);

  // Total mass 0.8 kg shared by the 33 movable nodes; pins have inverse mass 0.
  // Summing 35 values of ~0.024 kg: round-off below 64 eps.
  EXPECT_NEAR(sb.total_mass(), Real(0.8), 64 * kEps);
  const Real m_node = Real(0.8) / Real(nx * ny - 2);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const bool pin = j == 0 && (i == 0 || i == nx - 1);
      const btSoftBody::Node& n = b.m_nodes[g.at(i, j)];
      if (pin)
        EXPECT_EQ(n.m_im, Real(0)) << "pinned node (" << i << ", " << j << ")";
      else
        EXPECT_NEAR(n.m_im, Real(1) / m_node, 8 * kEps / m_node) << "node (" << i << ", " << j << ")";
    }

  // Each link joins the scene's particles, is not a Bullet-generated bending
  // link, and has kLST = 1 and the initial distance as rest length.
  for (int k = 0; k < b.m_links.size(); ++k) {
    const auto& d = scene.distances[static_cast<std::size_t>(k)];
    const btSoftBody::Link& l = b.m_links[k];
    EXPECT_EQ(l.m_n[0], &b.m_nodes[d.a]) << "link " << k;
    EXPECT_EQ(l.m_n[1], &b.m_nodes[d.b]) << "link " << k;
    EXPECT_EQ(l.m_bbending, 0) << "link " << k;
    EXPECT_EQ(l.m_material->m_kLST, Real(1));
    const Real rest = (scene.positions[static_cast<std::size_t>(d.a)] -
                       scene.positions[static_cast<std::size_t>(d.b)]).norm();
    EXPECT_NEAR(l.m_rl, rest, 4 * kEps * rest) << "link " << k;
  }
  EXPECT_EQ(b.m_cfg.piterations, 7);
  EXPECT_EQ(b.m_cfg.kDP, Real(0));
  EXPECT_EQ(b.m_cfg.kCHR, Real(1));
  EXPECT_EQ(b.m_cfg.kKHR, Real(1));
  EXPECT_EQ(b.getActivationState(), DISABLE_DEACTIVATION);
  // The soft body reads its own gravity, not the world's: it must be the
  // configured one (Bullet's default there is -10 m/s^2).
  EXPECT_EQ(b.m_worldInfo->m_gravity.y(), Real(-9.81));

  // Stepping adds no links, keeps the node count and leaves the pins in place.
  for (int f = 0; f < 5; ++f) sb.step_frame();
  EXPECT_EQ(sb.num_links(), links);
  EXPECT_EQ(sb.num_nodes(), nx * ny);
  std::vector<Vec3> x;
  sb.positions(x);
  for (const auto& [i, j] : c.pinned)
    EXPECT_EQ(x[static_cast<std::size_t>(g.at(i, j))], scene.positions[static_cast<std::size_t>(g.at(i, j))]);
}

// ---------------------------------------------------------------------------
// Free fall. btSoftBody integrates each internal step h as
//   predictMotion:    v += g h;  x_prev = x;  x += v h
//   solveConstraints: v = (x - x_prev) / h      (piterations >= 1, kDP = 0)
// i.e. symplectic Euler. Summing n steps from (x0, v0):
//   v_n = v0 + n g h,   x_n = x0 + n h v0 + g h^2 n (n + 1) / 2.
// Round-off: every step Bullet recomputes v = (x - x_prev)/h, a difference of
// two numbers of size |x| divided by h, so v picks up ~eps |x| / h per step.
// Those errors add up in v (n eps |x| / h after n steps) and add up again in
// x (n^2/2 eps |x|). The bounds below are twice that, with |x| + 1 for |x|.

struct FreeFallCase {
  Real dt;
  int internal_steps;
  int frames;
};

class SoftBodyFreeFall : public ::testing::TestWithParam<FreeFallCase> {};

TEST_P(SoftBodyFreeFall, MatchesDiscreteSymplecticEuler) {
  const FreeFallCase p = GetParam();
  const Vec3 x0(Real(0.3), Real(10), Real(-0.2));
  const Vec3 v0(Real(1), Real(2), Real(-0.5));
  xpbd::SceneDesc scene;
  scene.add_particle(x0, Real(2.5), Real(0), v0);

  SoftBodyBaselineConfig cfg;
  cfg.dt = p.dt;
  cfg.internal_steps = p.internal_steps;
  cfg.piterations = 3;
  cfg.gravity = Vec3(Real(0.5), Real(-9.81), Real(0));
  SoftBodyBaseline sb(scene, cfg);
  const auto frames = xpbd_bullet::run_recording_positions(sb, p.frames);
  ASSERT_EQ(frames.size(), static_cast<std::size_t>(p.frames + 1));

  const Real h = bullet_soft_step(p.dt / Real(p.internal_steps));
  auto x_ref = [&](Real n) { return Vec3(x0 + (n * h) * v0 + (h * h * n * (n + 1) / 2) * cfg.gravity); };
  // Every recorded frame f is after n = f * internal_steps internal steps.
  for (int f = 0; f <= p.frames; ++f) {
    const Real n = Real(f) * Real(p.internal_steps);
    ASSERT_EQ(frames[static_cast<std::size_t>(f)].size(), 1u);
    const Vec3 ref = x_ref(n);
    EXPECT_LT((frames[static_cast<std::size_t>(f)][0] - ref).norm(), (n * n + 1) * kEps * (ref.norm() + 1))
        << "frame " << f << ": x = " << frames[static_cast<std::size_t>(f)][0].transpose()
        << ", ref " << ref.transpose();
  }

  const Real n = Real(p.frames) * Real(p.internal_steps);
  const Vec3 v_ref = v0 + (n * h) * cfg.gravity;
  std::vector<Vec3> v;
  sb.velocities(v);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_LT((v[0] - v_ref).norm(), 2 * n * kEps * (x_ref(n).norm() + 1) / h)
      << "v = " << v[0].transpose() << ", ref " << v_ref.transpose();
  EXPECT_NEAR(sb.time(), Real(p.frames) * p.dt, 4 * kEps * Real(p.frames) * p.dt);
}

INSTANTIATE_TEST_SUITE_P(Steps, SoftBodyFreeFall,
                         ::testing::Values(FreeFallCase{Real(1) / Real(60), 1, 60},
                                           FreeFallCase{Real(1) / Real(60), 3, 60},
                                           FreeFallCase{Real(1) / Real(64), 1, 64}),
                         [](const ::testing::TestParamInfo<FreeFallCase>& i) {
                           return "dt1over" + std::to_string(std::lround(1 / i.param.dt)) + "_" +
                                  std::to_string(i.param.internal_steps) + "steps";
                         });

// In a double build, the soft body's step is float(h), not h: for h = 1/180 s
// float rounding changes h by 2.4e-8 relative, which moves a 1 s fall (about
// 5 m) by about 2.4e-7 m, five orders of magnitude above round-off. A
// reference built with the unrounded h must miss; the rounded one must not
// (checked in the test above).
TEST(SoftBodyFreeFall, BulletRoundsTheSoftBodyStepToFloat) {
  if constexpr (!std::is_same_v<btScalar, double>) GTEST_SKIP() << "float build: nothing to round";
  xpbd::SceneDesc scene;
  const Vec3 x0(Real(0), Real(10), Real(0));
  scene.add_particle(x0, Real(1));
  SoftBodyBaselineConfig cfg;
  cfg.internal_steps = 3;
  SoftBodyBaseline sb(scene, cfg);
  for (int f = 0; f < 60; ++f) sb.step_frame();
  std::vector<Vec3> x;
  sb.positions(x);
  const Real n = 180, h = cfg.dt / 3, hf = bullet_soft_step(h);
  const Vec3 x_unrounded = x0 + (h * h * n * (n + 1) / 2) * cfg.gravity;
  // The miss is g n(n+1)/2 (hf^2 - h^2), about 2.4e-7 m; round-off (see above)
  // is below n^2 eps (|x| + 1) = 8e-11 m.
  const Real miss = cfg.gravity.y() * n * (n + 1) / 2 * (hf * hf - h * h);
  EXPECT_GT(std::abs(miss), Real(1e-7));
  EXPECT_NEAR(x[0].y() - x_unrounded.y(), miss, n * n * kEps * (x0.norm() + 1));
}

// ---------------------------------------------------------------------------
// A single link from a pinned node to a free node hanging under gravity.
//
// In units of the rest length L, with s the link length before a projection,
// btSoftBody::PSolve_Links moves the free node along the link to length
//   f(s) = s (1 + kLST (1 - s^2) / (1 + s^2))
// (its linearised squared-length correction; f(1) = 1). At the steady state
// the node is at rest at length 1 + e; each internal step adds g h^2 to the
// length before the piterations projections, so e solves
//   f^p(1 + e + d) = 1 + e,   d = g h^2 / L.
// Expanding for one iteration: e = d (1 - k)/k - d^2 / (2 k^2) + O((d/k)^3).
// So with kLST = 1 the link hangs SHORTER than its rest length by d^2/2
// (1.5e-5 L for L = 0.5 m at 60 Hz), and with kLST < 1 it stretches by about
// d (1 - k)/k: the iteration-dependent stiffness of PBD.
//
// The reference e is the root of the steady-state equation, found by
// bisection here (independent of Bullet). The dynamics contract to that fixed
// point (linearised multiplier modulus sqrt(1 - k_eff) < 0.9 here), so after
// 600 steps only round-off is left: a few thousand ulp of L.

Real link_map(Real s, Real k) { return s * (1 + k * (1 - s * s) / (1 + s * s)); }

Real steady_strain(Real d, Real k, int p) {
  auto F = [&](Real e) {
    Real s = 1 + e + d;
    for (int i = 0; i < p; ++i) s = link_map(s, k);
    return s - (1 + e);  // > 0 below the root, < 0 above
  };
  Real lo = -2 * d, hi = 30 * d / k;
  for (int i = 0; i < 200; ++i) {
    const Real mid = (lo + hi) / 2;
    (F(mid) > 0 ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

struct HangCase {
  Real kLST;
  int piterations;
};

class SoftBodyHangingLink : public ::testing::TestWithParam<HangCase> {};

TEST_P(SoftBodyHangingLink, HangsAtTheSteadyStateOfBulletsLinkProjection) {
  const HangCase p = GetParam();
  const Real L = Real(0.5), m = Real(0.3), g = Real(9.81);
  xpbd::SceneDesc scene;
  const xpbd::Index top = scene.add_particle(Vec3::Zero(), 0);
  const xpbd::Index bob = scene.add_particle(Vec3(0, -L, 0), m);
  scene.pins.push_back(xpbd::PinDesc{top, std::nullopt, {}});
  scene.distances.push_back(xpbd::DistanceDesc{top, bob, std::nullopt, {}});

  SoftBodyBaselineConfig cfg;
  cfg.kLST = p.kLST;
  cfg.piterations = p.piterations;
  SoftBodyBaseline sb(scene, cfg);
  for (int f = 0; f < 600; ++f) sb.step_frame();

  std::vector<Vec3> x;
  sb.positions(x);
  EXPECT_EQ(x[0], Vec3::Zero()) << "the pinned node must not move";
  EXPECT_EQ(x[1].x(), Real(0));
  EXPECT_EQ(x[1].z(), Real(0));
  const Real e = -x[1].y() / L - 1;

  const Real h = bullet_soft_step(cfg.dt);
  const Real d = g * h * h / L;
  const Real tol = std::max(Real(1e-12), 4096 * kEps);
  EXPECT_NEAR(e, steady_strain(d, p.kLST, p.piterations), tol);
  if (p.piterations == 1) {
    // The closed-form expansion; its next term is below (d/k)^3 (coefficient ~1).
    const Real dk = d / p.kLST;
    EXPECT_NEAR(e, d * (1 - p.kLST) / p.kLST - dk * dk / 2, 2 * dk * dk * dk + tol);
  }
  if (p.kLST == Real(1)) {
    // kLST = 1: the stretch is second order in d, far below the unconstrained
    // per-step sag d (5.45e-3): |e| <= d^2/2 (+ round-off).
    EXPECT_LE(std::abs(e), d * d / 2 * Real(1.01) + tol);
  }
}

INSTANTIATE_TEST_SUITE_P(StiffnessAndIterations, SoftBodyHangingLink,
                         ::testing::Values(HangCase{Real(1), 1}, HangCase{Real(0.5), 1},
                                           HangCase{Real(1), 10}, HangCase{Real(0.3), 2}),
                         [](const ::testing::TestParamInfo<HangCase>& i) {
                           return "kLST" + std::to_string(std::lround(i.param.kLST * 10)) +
                                  "tenths_" + std::to_string(i.param.piterations) + "iter";
                         });

// A rest length different from the initial distance must be honoured (Bullet
// alone would reset it to the initial distance on its first step). The bob
// starts 1 m below the pin with a 0.6 m rest length; with kLST = 1 and 10
// iterations it settles at 0.6 m to within the steady-state strain
// (|e| < 1e-12, from the fixed point above) and round-off.
TEST(SoftBodyBaseline, HonoursExplicitRestLengths) {
  xpbd::SceneDesc scene;
  const xpbd::Index top = scene.add_particle(Vec3::Zero(), 0);
  const xpbd::Index bob = scene.add_particle(Vec3(0, -1, 0), Real(0.2));
  scene.pins.push_back(xpbd::PinDesc{top, std::nullopt, {}});
  scene.distances.push_back(xpbd::DistanceDesc{top, bob, Real(0.6), {}});
  SoftBodyBaseline sb(scene, SoftBodyBaselineConfig{});
  EXPECT_EQ(sb.body().m_links[0].m_rl, Real(0.6));
  for (int f = 0; f < 300; ++f) sb.step_frame();
  std::vector<Vec3> x;
  sb.positions(x);
  EXPECT_NEAR(-x[1].y(), Real(0.6), std::max(Real(1e-10), 4096 * kEps));
}

// ---------------------------------------------------------------------------
// Bad input: a clear error naming the field and value, never a crash.

TEST(SoftBodyBaseline, RejectsInvalidConfigNamingTheField) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3::Zero(), 1);
  auto message = [&](SoftBodyBaselineConfig cfg) -> std::string {
    try {
      SoftBodyBaseline sb(scene, cfg);
    } catch (const xpbd::ConfigError& e) {
      return e.what();
    }
    return "";
  };
  SoftBodyBaselineConfig c;
  c.kLST = 0;
  EXPECT_NE(message(c).find("kLST"), std::string::npos);
  c = {};
  c.kLST = Real(1.5);
  EXPECT_NE(message(c).find("1.5"), std::string::npos);
  c = {};
  c.piterations = 0;
  EXPECT_NE(message(c).find("piterations"), std::string::npos);
  c = {};
  c.internal_steps = -2;
  EXPECT_NE(message(c).find("internal_steps: must be >= 1, got -2"), std::string::npos);
  c = {};
  c.dt = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_NE(message(c).find("dt"), std::string::npos);
}

TEST(SoftBodyBaseline, RejectsSceneElementsItCannotRepresent) {
  auto message = [](const xpbd::SceneDesc& s) -> std::string {
    try {
      SoftBodyBaseline sb(s, SoftBodyBaselineConfig{});
    } catch (const xpbd::SceneError& e) {
      return e.what();
    }
    return "";
  };
  xpbd::SceneDesc base;
  base.add_particle(Vec3::Zero(), 1);
  base.add_particle(Vec3(1, 0, 0), 1);

  xpbd::SceneDesc s = base;
  s.planes.push_back(xpbd::PlaneDesc{});
  EXPECT_NE(message(s).find("planes"), std::string::npos);

  s = base;
  s.pins.push_back(xpbd::PinDesc{1, std::nullopt, {}});  // pin on a particle of mass 1 kg
  EXPECT_NE(message(s).find("pins[0].particle"), std::string::npos);

  s = base;
  s.distances.push_back(xpbd::DistanceDesc{0, 7, std::nullopt, {}});  // out of range (compile)
  EXPECT_NE(message(s).find("distances[0].b"), std::string::npos);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
