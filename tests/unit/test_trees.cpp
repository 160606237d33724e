// The direct solve over trees of Distance elements (xpbd/trees.hpp,
// StepConfig::direct_chains): which elements form trees, and the static
// stretch of a hanging branched structure against its closed form.
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
// Relative error of a stretch the direct solve must reach: round-off (as
// test_chains.cpp: in float the stretch is a difference of positions about
// 1 m from the origin).
constexpr Real kRoundOff = sizeof(Real) == 8 ? Real(1e-9) : Real(0.05);

xpbd::DistanceDesc edge(Index a, Index b, Real damping = 0) {
  xpbd::DistanceDesc d{a, b, Real(0.1), {}};
  d.mat.damping = damping;
  return d;
}

// n particles of 1 kg; those listed in `pinned` of mass 0 (inverse mass 0).
xpbd::SceneDesc points(int n, std::vector<int> pinned = {}) {
  xpbd::SceneDesc s;
  for (int i = 0; i < n; ++i) {
    const bool pin = std::find(pinned.begin(), pinned.end(), i) != pinned.end();
    s.add_particle(Vec3(Real(0.1) * Real(i), 0, 0), pin ? 0 : 1, 0);
  }
  return s;
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
