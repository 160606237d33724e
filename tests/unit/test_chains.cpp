// The direct solve along chains (xpbd/chains.hpp, StepConfig::direct_chains):
// which elements form chains, and the static stretch of a hanging chain
// against its closed form, with and without a heavy rigid end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "xpbd/xpbd.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;

constexpr Real kG = Real(9.81);
// Relative error of a stretch the direct solve must reach: round-off. In
// float, the stretch (1e-5 to 2e-4 m) is a difference of positions about
// 1 m from the origin, whose spacing is 6e-8 m near 1 m.
constexpr Real kRoundOff = sizeof(Real) == 8 ? Real(1e-9) : Real(0.05);

xpbd::DistanceDesc edge(Index a, Index b, Real damping = 0) {
  xpbd::DistanceDesc d{a, b, Real(0.1), {}};
  d.mat.damping = damping;
  return d;
}

xpbd::SceneDesc points(int n) {
  xpbd::SceneDesc s;
  for (int i = 0; i < n; ++i) s.add_particle(Vec3(Real(0.1) * Real(i), 0, 0), 1, 0);
  return s;
}

TEST(FindChains, ARopeIsOneChainInPathOrder) {
  xpbd::SceneDesc s = points(5);
  // Elements listed out of order and reversed: the chain follows the path.
  s.distances = {edge(3, 2), edge(0, 1), edge(4, 3), edge(1, 2)};
  const xpbd::Model m = xpbd::compile(s);
  ASSERT_EQ(m.chains.size(), 1);
  EXPECT_EQ(m.chains.particle, (std::vector<Index>{0, 1, 2, 3, 4}));
  EXPECT_EQ(m.chains.element, (std::vector<Index>{1, 3, 0, 2}));
  EXPECT_EQ(m.chains.end_of[0], 0);
  EXPECT_EQ(m.chains.end_of[4], 1);
  EXPECT_EQ(m.chains.end_of[2], -1);
}

TEST(FindChains, BranchesDampingLoopsAndSingleElements) {
  // A star: three arms of two elements from particle 0; every arm is a chain.
  xpbd::SceneDesc star = points(7);
  star.distances = {edge(0, 1), edge(1, 2), edge(0, 3), edge(3, 4), edge(0, 5), edge(5, 6)};
  EXPECT_EQ(xpbd::compile(star).chains.size(), 3);
  // A damped element in the middle of a rope ends the chains on either side.
  xpbd::SceneDesc damped = points(6);
  damped.distances = {edge(0, 1), edge(1, 2), edge(2, 3, 0.5), edge(3, 4), edge(4, 5)};
  const xpbd::Model md = xpbd::compile(damped);
  ASSERT_EQ(md.chains.size(), 2);
  EXPECT_EQ(md.chains.particle, (std::vector<Index>{0, 1, 2, 3, 4, 5}));
  // A closed loop is not a chain, and neither is a single element.
  xpbd::SceneDesc ring = points(4);
  ring.distances = {edge(0, 1), edge(1, 2), edge(2, 3), edge(3, 0)};
  EXPECT_EQ(xpbd::compile(ring).chains.size(), 0);
  // A loop that leaves a branching particle and comes back to it.
  xpbd::SceneDesc lollipop = points(4);
  lollipop.distances = {edge(0, 1), edge(1, 2), edge(2, 3), edge(3, 1)};
  EXPECT_EQ(xpbd::compile(lollipop).chains.size(), 0);
  xpbd::SceneDesc one = points(2);
  one.distances = {edge(0, 1)};
  EXPECT_EQ(xpbd::compile(one).chains.size(), 0);
}

// A chain of `links` links of rest length L hanging from a pinned particle,
// particles of mass m, compliance alpha; optionally a body of mass M hanging
// from the last particle by an attachment at compliance 0.
struct Hanging {
  int links = 20;
  Real L = Real(0.1), m = Real(0.1), alpha = Real(1e-5), M = 0;
};

// Force carried by link j (joining particles j and j + 1): the weight below.
Real link_force(const Hanging& c, int j) { return (Real(c.links - j) * c.m + c.M) * kG; }

struct ChainRun {
  Real worst_rel_error = 0;  // max over links of |stretch - alpha F| / (alpha F)
  Real body_drift = 0;       // m, how far the body moved
  bool finite = true;
};

ChainRun run_hanging(const Hanging& c, bool direct, bool coloured, int steps) {
  xpbd::SceneDesc scene;
  xpbd::RopeDesc r;
  r.n = c.links + 1;
  r.start = Vec3(0, 0, 0);
  r.dir = Vec3(0, -1, 0);
  r.spacing = c.L;
  r.mass = c.m;
  r.mat.compliance = c.alpha;
  xpbd::add_rope(scene, r);
  const xpbd::Model model = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(model);
  // Start at the closed-form equilibrium: link j stretched by alpha F_j.
  Real y = 0;
  for (int j = 0; j < c.links; ++j) {
    y -= c.L + c.alpha * link_force(c, j);
    s.x[std::size_t(j + 1)] = Vec3(0, y, 0);
  }
  Vec3 body_start = Vec3::Zero();
  if (c.M > 0) {
    xpbd::RigidBody b;
    b.inv_mass = Real(1) / c.M;
    b.inv_inertia = Vec3::Constant(Real(1) / (c.M * Real(0.01)));
    b.x = Vec3(0, y - Real(0.1), 0);  // attachment 0.1 m above its centre
    b.accel = Vec3(0, -kG, 0);
    s.bodies.push_back(b);
    s.attachments.push_back(xpbd::BodyAttachment{static_cast<Index>(c.links), 0, Vec3(0, Real(0.1), 0), 0});
    body_start = b.x;
  }
  xpbd::StepConfig cfg;
  cfg.substeps = 10;
  cfg.iterations = 1;
  cfg.direct_chains = direct;
  cfg.coloured = coloured;
  cfg.chain_tolerance = 0;  // every pass: converge to round-off
  for (int k = 0; k < steps; ++k) xpbd::step(model, s, cfg);
  ChainRun out;
  for (int j = 0; j < c.links; ++j) {
    const Real stretch = (s.x[std::size_t(j + 1)] - s.x[std::size_t(j)]).norm() - c.L;
    const Real expect = c.alpha * link_force(c, j);
    out.worst_rel_error = std::max(out.worst_rel_error, std::abs(stretch - expect) / expect);
  }
  for (const Vec3& p : s.x) out.finite = out.finite && p.allFinite();
  if (c.M > 0) out.body_drift = (s.bodies[0].x - body_start).norm();
  return out;
}

// One sweep per substep leaves a stiff hanging chain longer than its
// compliance says (by about g h^2 per link and substep, summed down the
// chain); the direct solve holds the closed form, alpha times the weight
// below each link, for a second (60 steps of 10 x 1).
TEST(DirectChains, HangingChainHoldsItsClosedFormStretch) {
  const Hanging c;
  for (bool coloured : {false, true}) {
    SCOPED_TRACE(coloured ? "coloured" : "array order");
    const ChainRun swept = run_hanging(c, false, coloured, 60);
    const ChainRun direct = run_hanging(c, true, coloured, 60);
    // Measured (double): the sweep off by 3.1 (array order) and 6.7
    // (coloured) times the stretch itself, the direct solve by 7e-12.
    EXPECT_GT(swept.worst_rel_error, Real(1));
    EXPECT_LT(direct.worst_rel_error, kRoundOff);
  }
}

// A body 100 times the chain's mass, at its end by an attachment: the
// attachment is a row of the same solve, with the body's inverse mass.
TEST(DirectChains, HeavyBodyAtTheEndHoldsItsClosedFormStretch) {
  Hanging c;
  c.links = 10;
  c.M = 100 * Real(c.links) * c.m;  // 100 kg
  const ChainRun swept = run_hanging(c, false, false, 60);
  const ChainRun direct = run_hanging(c, true, false, 60);
  // Measured (double): the sweep off by 1.7 times the stretch, the body
  // 16 cm below its rest; the direct solve 6e-15 and 0 m.
  EXPECT_GT(swept.worst_rel_error, Real(1));
  EXPECT_GT(swept.body_drift, Real(0.01));
  EXPECT_LT(direct.worst_rel_error, kRoundOff);
  // The top link's alpha F is 1e-5 * 101 * 9.81 = 1 cm; the body stays
  // within a thousandth of it.
  EXPECT_LT(direct.body_drift, Real(1e-5));
}

// A taut straight chain between two kinematic ends at compliance 0 has a
// singular system (the links cannot all reach their rest length); the
// direct solve leaves it to the sweep: the same result as without it.
TEST(DirectChains, SingularChainIsLeftToTheSweep) {
  xpbd::SceneDesc scene;
  for (int i = 0; i < 5; ++i) scene.add_particle(Vec3(Real(0.11) * Real(i), 0, 0), i == 0 || i == 4 ? 0 : 1, 0);
  for (Index i = 0; i < 4; ++i) scene.distances.push_back(xpbd::DistanceDesc{i, i + 1, Real(0.1), {}});
  const xpbd::Model m = xpbd::compile(scene);
  ASSERT_EQ(m.chains.size(), 1);
  xpbd::StepConfig cfg;
  cfg.gravity = Vec3::Zero();
  xpbd::State a = xpbd::make_state(m), b = xpbd::make_state(m);
  cfg.direct_chains = true;
  for (int k = 0; k < 10; ++k) xpbd::step(m, a, cfg);
  cfg.direct_chains = false;
  for (int k = 0; k < 10; ++k) xpbd::step(m, b, cfg);
  for (std::size_t i = 0; i < a.x.size(); ++i) {
    EXPECT_TRUE(a.x[i].allFinite());
    EXPECT_EQ(a.x[i], b.x[i]) << "particle " << i;
  }
}

TEST(DirectChains, BadConfigurationsAreNamed) {
  xpbd::SceneDesc scene = points(3);
  scene.distances = {edge(0, 1), edge(1, 2)};
  xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  auto message = [&](const xpbd::StepConfig& cfg) {
    try {
      xpbd::step(m, s, cfg);
    } catch (const xpbd::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  xpbd::StepConfig cfg;
  cfg.direct_chains = true;
  cfg.method = xpbd::Method::pbd;
  EXPECT_NE(message(cfg).find("direct_chains: needs method xpbd"), std::string::npos);
  cfg.method = xpbd::Method::xpbd;
  cfg.chain_passes = 0;
  EXPECT_NE(message(cfg).find("chain_passes: must be >= 1, got 0"), std::string::npos);
  cfg.chain_passes = 4;
  cfg.chain_tolerance = std::nan("");
  EXPECT_NE(message(cfg).find("chain_tolerance"), std::string::npos);
  cfg.chain_tolerance = 0;
  // An element added after compile(): the chains no longer describe the model.
  m.get<xpbd::Distance>().push_back(m.get<xpbd::Distance>()[0]);
  s = xpbd::make_state(m);
  EXPECT_NE(message(cfg).find("use compile"), std::string::npos);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
