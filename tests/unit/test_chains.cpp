// The direct solves of StepConfig::direct_chains: along chains
// (xpbd/chains.hpp): which elements form chains, and the static stretch of
// a hanging chain against its closed form, with and without a heavy rigid
// end; over trees (xpbd/trees.hpp): which elements form trees, a hanging
// broom against its closed form, swinging trees against their own
// constraints, and a free one's momentum.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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

// n particles of 1 kg along x; those listed in `pinned` of mass 0
// (inverse mass 0).
xpbd::SceneDesc points(int n, const std::vector<int>& pinned = {}) {
  xpbd::SceneDesc s;
  for (int i = 0; i < n; ++i) {
    const bool pin = std::find(pinned.begin(), pinned.end(), i) != pinned.end();
    s.add_particle(Vec3(Real(0.1) * Real(i), 0, 0), pin ? 0 : 1, 0);
  }
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

// Every node of every tree once, each before its parent, each element node
// between its particles' nodes.
void expect_well_formed(const xpbd::Model& m) {
  const xpbd::Trees& t = m.trees;
  for (Index k = 0; k < t.size(); ++k) {
    const Index b = t.begin[std::size_t(k)], e = t.begin[std::size_t(k) + 1];
    EXPECT_EQ(t.parent[std::size_t(e - 1)], -1);
    for (Index j = b; j < e - 1; ++j) {
      const Index p = t.parent[std::size_t(j)];
      ASSERT_GT(p, j);
      ASSERT_LT(p, e);
      EXPECT_NE(t.element[std::size_t(j)], t.element[std::size_t(p)]);
      const Index el = t.element[std::size_t(j)] ? t.index[std::size_t(j)] : t.index[std::size_t(p)];
      const Index pa = t.element[std::size_t(j)] ? t.index[std::size_t(p)] : t.index[std::size_t(j)];
      const auto& d = m.get<xpbd::Distance>()[std::size_t(el)];
      EXPECT_TRUE(d.p[0] == pa || d.p[1] == pa);
    }
  }
}

TEST(FindTrees, BranchedStructuresWithoutLoopsAreTrees) {
  // A star: three arms of two elements from particle 0: one tree of 7
  // particles and 6 elements.
  xpbd::SceneDesc star = points(7);
  star.distances = {edge(0, 1), edge(1, 2), edge(0, 3), edge(3, 4), edge(0, 5), edge(5, 6)};
  const xpbd::Model ms = xpbd::compile(star);
  ASSERT_EQ(ms.trees.size(), 1);
  EXPECT_EQ(ms.trees.index.size(), 13u);
  expect_well_formed(ms);
  // The same with its three arm ends pinned: the pins are no nodes.
  xpbd::SceneDesc pinned = points(7, {2, 4, 6});
  pinned.distances = star.distances;
  const xpbd::Model mp = xpbd::compile(pinned);
  ASSERT_EQ(mp.trees.size(), 1);
  EXPECT_EQ(mp.trees.index.size(), 10u);
  expect_well_formed(mp);
  // A path is a chain's, a loop is nobody's, a damped element is left out
  // (which leaves the star's other two arms a path), and a loop behind a
  // branching particle makes the whole set no tree.
  xpbd::SceneDesc path = points(4);
  path.distances = {edge(0, 1), edge(1, 2), edge(2, 3)};
  EXPECT_EQ(xpbd::compile(path).trees.size(), 0);
  xpbd::SceneDesc damped = points(7);
  damped.distances = star.distances;
  damped.distances[2].mat.damping = Real(0.5);
  EXPECT_EQ(xpbd::compile(damped).trees.size(), 0);
  xpbd::SceneDesc looped = points(7);
  looped.distances = star.distances;
  looped.distances.push_back(edge(2, 4));
  EXPECT_EQ(xpbd::compile(looped).trees.size(), 0);
  // Two arms to the same pin close no loop through a moving particle.
  xpbd::SceneDesc to_pin = points(5, {4});
  to_pin.distances = {edge(0, 1), edge(0, 2), edge(0, 3), edge(1, 4), edge(2, 4)};
  EXPECT_EQ(xpbd::compile(to_pin).trees.size(), 1);
  // A cloth has loops everywhere.
  xpbd::SceneDesc cloth;
  xpbd::ClothGridDesc c;
  c.nx = c.ny = 4;
  xpbd::add_cloth_grid(cloth, c);
  EXPECT_EQ(xpbd::compile(cloth).trees.size(), 0);
}

// A broom hanging from a pin: a trunk of `trunk` links straight down to a
// junction, and `branches` branches of `links` links each hanging straight
// down from it (on the same vertical line), each ending in a weight of
// mass M; particles of mass m, every link of rest L and compliance alpha.
// At rest each link is stretched by alpha times the weight below it.
struct Broom {
  int trunk = 4, branches = 3, links = 4;
  Real L = Real(0.1), m = Real(0.01), M = Real(1), alpha = Real(1e-5);
};

struct BroomRun {
  Real worst_rel_error = 0;  // max over links of |stretch - alpha F| / (alpha F)
  Real worst_stretch = 0;    // m, max over links of |stretch - alpha F|
  bool finite = true;
  Index trees = 0;
};

BroomRun run_broom(const Broom& b, bool direct, bool coloured, int steps) {
  xpbd::SceneDesc scene;
  // Particle 0 the pin, 1 .. trunk down the trunk (the last is the
  // junction), then each branch's particles top to bottom.
  const Real branch_weight = (Real(b.links - 1) * b.m + b.M) * kG;
  std::vector<Real> force;  // per element, the weight below it
  std::vector<std::pair<Index, Index>> links;
  scene.add_particle(Vec3::Zero(), 0);
  for (int j = 1; j <= b.trunk; ++j) {
    scene.add_particle(Vec3::Zero(), b.m);
    links.emplace_back(j - 1, j);
    force.push_back(Real(b.branches) * branch_weight + Real(b.trunk - j + 1) * b.m * kG);
  }
  const Index junction = b.trunk;
  for (int k = 0; k < b.branches; ++k)
    for (int j = 1; j <= b.links; ++j) {
      const Index p = scene.add_particle(Vec3::Zero(), j == b.links ? b.M : b.m);
      links.emplace_back(j == 1 ? junction : p - 1, p);
      force.push_back((Real(b.links - j) * b.m + b.M) * kG);
    }
  for (const auto& [a, c] : links) {
    xpbd::DistanceDesc d{a, c, b.L, {}};
    d.mat.compliance = b.alpha;
    scene.distances.push_back(d);
  }
  // Start at the closed form: each particle below its upper neighbour by
  // L + alpha F.
  for (std::size_t e = 0; e < links.size(); ++e) {
    const auto [a, c] = links[e];
    scene.positions[std::size_t(c)] = scene.positions[std::size_t(a)] - Vec3(0, b.L + b.alpha * force[e], 0);
  }
  const xpbd::Model model = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(model);
  xpbd::StepConfig cfg;
  cfg.substeps = 10;
  cfg.iterations = 1;
  cfg.direct_chains = direct;
  cfg.coloured = coloured;
  cfg.chain_tolerance = 0;  // every pass: converge to round-off
  for (int k = 0; k < steps; ++k) xpbd::step(model, s, cfg);
  BroomRun out;
  out.trees = model.trees.size();
  for (std::size_t e = 0; e < links.size(); ++e) {
    const auto [a, c] = links[e];
    const Real stretch = (s.x[std::size_t(c)] - s.x[std::size_t(a)]).norm() - b.L;
    const Real expect = b.alpha * force[e];
    out.worst_stretch = std::max(out.worst_stretch, std::abs(stretch - expect));
    if (expect > 0) out.worst_rel_error = std::max(out.worst_rel_error, std::abs(stretch - expect) / expect);
  }
  for (const Vec3& p : s.x) out.finite = out.finite && p.allFinite();
  return out;
}

// Three 1 kg weights on branches of 10 g particles, 100 times the mass of
// a particle: the sweep, and the chains' solves one branch at a time,
// carry the weights' load across the junction a little per sweep; the tree
// solve holds the closed form for a second (60 steps of 10 x 1).
TEST(DirectTrees, HangingBroomHoldsItsClosedFormStretch) {
  const Broom b;
  for (bool coloured : {false, true}) {
    SCOPED_TRACE(coloured ? "coloured" : "array order");
    const BroomRun swept = run_broom(b, false, coloured, 60);
    const BroomRun direct = run_broom(b, true, coloured, 60);
    ASSERT_EQ(direct.trees, 1);
    EXPECT_TRUE(direct.finite);
    std::printf("%s: worst link off its closed-form stretch by %.3g (sweep), %.3g (direct) times it\n",
                coloured ? "coloured" : "array order", double(swept.worst_rel_error), double(direct.worst_rel_error));
    EXPECT_GT(swept.worst_rel_error, Real(1));
    EXPECT_LT(direct.worst_rel_error, kRoundOff);
  }
}

// At compliance 0 every link is rigid, and the element to the pin has no
// particle below it in the tree: it takes the solve's smallest pivot
// instead of a zero one. The links stay at their rest length to round-off,
// where the sweep leaves them stretched.
TEST(DirectTrees, RigidBroomKeepsItsLengths) {
  Broom b;
  b.alpha = 0;
  const BroomRun swept = run_broom(b, false, false, 60);
  const BroomRun direct = run_broom(b, true, false, 60);
  EXPECT_TRUE(direct.finite);
  std::printf("rigid: worst link stretched %.3g m (sweep), %.3g m (direct)\n", double(swept.worst_stretch),
              double(direct.worst_stretch));
  EXPECT_GT(swept.worst_stretch, Real(1e-3));
  EXPECT_LT(direct.worst_stretch, sizeof(Real) == 8 ? Real(1e-9) : Real(1e-5));
}

// Trees whose elements point every way (a trunk from a pin with three arms
// of different lengths and directions and 0.5 kg tips; a "V" from two
// pins whose junction, with two elements to pins, takes the saddle-point
// block, and carries an arm), or a free one spinning without gravity.
struct Trees3D {
  xpbd::SceneDesc scene;
  Index particle(const Vec3& x, Real m) { return scene.add_particle(x, m); }
  void link(Index a, Index b) {
    xpbd::DistanceDesc d{a, b, (scene.positions[std::size_t(a)] - scene.positions[std::size_t(b)]).norm(), {}};
    d.mat.compliance = Real(1e-6);
    scene.distances.push_back(d);
  }
  // Three arms from `junction`, the a-th of a + 1 links.
  void arms(Index junction) {
    const Vec3 dirs[3] = {Vec3(1, 0, 0), Vec3(0, Real(-0.3), 1), Vec3(Real(0.2), Real(0.5), Real(-1))};
    for (int a = 0; a < 3; ++a) {
      Index prev = junction;
      for (int k = 1; k <= a + 1; ++k) {
        const Index p = particle(scene.positions[std::size_t(prev)] + Real(0.1) * dirs[a].normalized(),
                                 k == a + 1 ? Real(0.5) : Real(0.05));
        link(prev, p);
        prev = p;
      }
    }
  }
};

// The largest |C + alpha/h^2 lambda| over rest length of the Distance
// elements after a step (the last substep's multipliers, array order).
Real worst_residual(const xpbd::Model& m, const xpbd::State& s, Real h) {
  Real worst = 0;
  const auto& el = m.get<xpbd::Distance>();
  for (std::size_t k = 0; k < el.size(); ++k) {
    const Real len = (s.x[std::size_t(el[k].p[0])] - s.x[std::size_t(el[k].p[1])]).norm();
    const Real r = len - el[k].rest + el[k].mat.compliance / (h * h) * s.lambdas<xpbd::Distance>()[k];
    worst = std::max(worst, std::abs(r) / el[k].rest);
  }
  return worst;
}

// Every element of both trees ends each step with its constraint solved,
// C + alpha/h^2 lambda = 0, to round-off, while they swing: Newton's
// passes converge only if the elimination's couplings and signs are right,
// whatever the directions. One sweep per substep leaves them far from it.
TEST(DirectTrees, SwingingTreesEndEveryStepSolved) {
  Trees3D t;
  const Index pin = t.particle(Vec3(0, 1, 0), 0);
  const Index t1 = t.particle(Vec3(Real(0.1), 1, 0), Real(0.05));
  const Index junction = t.particle(Vec3(Real(0.2), Real(0.95), 0), Real(0.05));
  t.link(pin, t1);
  t.link(t1, junction);
  t.arms(junction);
  const Index left = t.particle(Vec3(-1, 1, 0), 0), right = t.particle(Vec3(Real(-0.6), 1, 0), 0);
  const Index v = t.particle(Vec3(Real(-0.8), Real(0.9), 0), Real(0.2));
  t.link(left, v);
  t.link(right, v);
  const Index v1 = t.particle(Vec3(Real(-0.8), Real(0.9), Real(0.15)), Real(0.05));
  const Index v2 = t.particle(Vec3(Real(-0.8), Real(0.85), Real(0.3)), Real(0.5));
  t.link(v, v1);
  t.link(v1, v2);
  t.link(v, t.particle(Vec3(Real(-0.7), Real(0.8), 0), Real(0.1)));
  const xpbd::Model m = xpbd::compile(t.scene);
  ASSERT_EQ(m.trees.size(), 2);
  xpbd::State direct = xpbd::make_state(m), swept = xpbd::make_state(m);
  xpbd::StepConfig cfg;
  cfg.substeps = 10;
  cfg.chain_tolerance = 0;
  const Real h = cfg.dt / Real(cfg.substeps);
  Real worst_direct = 0, worst_swept = 0;
  for (int k = 0; k < 30; ++k) {
    cfg.direct_chains = true;
    xpbd::step(m, direct, cfg);
    cfg.direct_chains = false;
    xpbd::step(m, swept, cfg);
    worst_direct = std::max(worst_direct, worst_residual(m, direct, h));
    worst_swept = std::max(worst_swept, worst_residual(m, swept, h));
  }
  std::printf("largest residual over rest length after a step: %.3g (direct), %.3g (sweep)\n",
              double(worst_direct), double(worst_swept));
  EXPECT_GT((direct.x.back() - m.x0.back()).norm(), Real(0.05));  // it swung
  EXPECT_GT(worst_swept, Real(1e-3));
  EXPECT_LT(worst_direct, sizeof(Real) == 8 ? Real(1e-9) : Real(1e-3));
}

// A free tree spinning without gravity: every correction of the solve is
// W J^T dlambda, equal and opposite along each element, so the linear
// momentum stays what it was, to round-off. (Not the angular momentum of
// the velocities (x - x_prev) / h: a correction along the element at the
// current positions turns it by (dlambda / h) n x (x_prev,a - x_prev,b),
// in the sweep too.)
TEST(DirectTrees, FreeSpinningTreeKeepsItsLinearMomentum) {
  Trees3D t;
  const Index junction = t.particle(Vec3(0, 1, 0), Real(0.3));
  const Index up = t.particle(Vec3(0, Real(1.1), 0), Real(0.1));
  t.link(junction, up);
  t.arms(junction);
  for (std::size_t i = 0; i < t.scene.positions.size(); ++i)
    t.scene.velocities.push_back(Vec3(0, 0, 3).cross(t.scene.positions[i] - Vec3(0, 1, 0)) + Vec3(Real(0.1) * Real(i), 0, 0));
  const xpbd::Model m = xpbd::compile(t.scene);
  ASSERT_EQ(m.trees.size(), 1);
  xpbd::State s = xpbd::make_state(m);
  auto momentum = [&] {
    Vec3 p = Vec3::Zero();
    for (std::size_t i = 0; i < s.x.size(); ++i) p += s.v[i] / m.inv_mass[i];
    return p;
  };
  const Vec3 p0 = momentum();
  xpbd::StepConfig cfg;
  cfg.gravity = Vec3::Zero();
  cfg.direct_chains = true;
  cfg.chain_tolerance = 0;
  for (int k = 0; k < 30; ++k) xpbd::step(m, s, cfg);
  const Vec3 p1 = momentum();
  const Real h = cfg.dt / Real(cfg.substeps);
  std::printf("momentum change %.3g kg m/s (of %.3g); residual %.3g\n", double((p1 - p0).norm()), double(p0.norm()),
              double(worst_residual(m, s, h)));
  // Float: each velocity (x - x_prev) / h carries about eps |x| / (|v| h),
  // 4e-5 of it here, in each of the 300 substeps (measured: 1.6e-3).
  EXPECT_LT((p1 - p0).norm(), (sizeof(Real) == 8 ? Real(1e-10) : Real(1e-2)) * (Real(1) + p0.norm()));
  EXPECT_LT(worst_residual(m, s, h), sizeof(Real) == 8 ? Real(1e-9) : Real(1e-3));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
