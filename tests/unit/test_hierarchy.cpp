// Hierarchical PBD (xpbd/src/hierarchy.hpp, StepConfig::hierarchy): the
// levels of a rope against their closed forms (particles, rest lengths,
// masses, weights), the invariants of a cloth's levels, a step below the
// slack that is bit for bit the plain step, the stretch the pass removes
// from a stiff rope, and the checks of the slack.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "../../xpbd/src/hierarchy.hpp"
#include "xpbd/xpbd.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;

constexpr Real kTight = sizeof(Real) == 8 ? Real(1e-12) : Real(1e-5);

xpbd::SceneDesc rope(int n, Real spacing, Real mass, Real compliance) {
  xpbd::SceneDesc s;
  xpbd::RopeDesc d;
  d.n = n;
  d.spacing = spacing;
  d.mass = mass;
  d.mat.compliance = compliance;
  xpbd::add_rope(s, d);
  return s;
}

// A rope of 33 particles pinned at 0: level 1 is the even particles, level 2
// every fourth; 5 would be left for a third level, below the 8 a level needs.
TEST(Hierarchy, RopeLevelsInClosedForm) {
  const Real l = Real(0.01), m = Real(0.002);
  const xpbd::Model model = xpbd::compile(rope(33, l, m, 0));
  const auto h = xpbd::detail::build_hierarchy(model);
  ASSERT_EQ(h->levels.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    const auto& lev = h->levels[static_cast<std::size_t>(k)];
    const int step = 2 << k;  // 2, then 4
    const int count = 32 / step + 1;
    ASSERT_EQ(lev.particles.size(), static_cast<std::size_t>(count)) << "level " << k + 1;
    for (int c = 0; c < count; ++c) EXPECT_EQ(lev.particles[static_cast<std::size_t>(c)], c * step);
    // Edges between neighbours, rest = the path along the rope.
    ASSERT_EQ(lev.edges.size(), static_cast<std::size_t>(count - 1));
    for (std::size_t e = 0; e < lev.edges.size(); ++e) {
      EXPECT_EQ(std::abs(lev.edges[e][0] - lev.edges[e][1]), 1);
      EXPECT_NEAR(lev.rest[e], Real(step) * l, kTight * l * Real(step));
    }
    // Mass: own plus half of each movable child's (equal rests, two
    // parents): interior 2m, then 4m; the free end 1.5m, then 2.5m; the pin
    // stays kinematic.
    const Real interior = Real(step) * m, end = k == 0 ? Real(1.5) * m : Real(2.5) * m;
    EXPECT_EQ(lev.inv_mass[0], 0);
    for (int c = 1; c + 1 < count; ++c)
      EXPECT_NEAR(lev.inv_mass[static_cast<std::size_t>(c)], 1 / interior, kTight / interior) << c;
    EXPECT_NEAR(lev.inv_mass.back(), 1 / end, kTight / end);
    // Children: the finer level's odd positions, halfway between two parents.
    ASSERT_EQ(lev.child.size(), static_cast<std::size_t>(count - 1));
    for (std::size_t c = 0; c < lev.child.size(); ++c) {
      const Index i = lev.child[c];
      EXPECT_EQ(i % step, step / 2);
      ASSERT_EQ(lev.parent_begin[c + 1] - lev.parent_begin[c], 2);
      for (Index j = lev.parent_begin[c]; j < lev.parent_begin[c + 1]; ++j) {
        EXPECT_EQ(std::abs(lev.parent[static_cast<std::size_t>(j)] - i), step / 2);
        EXPECT_NEAR(lev.weight[static_cast<std::size_t>(j)], Real(0.5), kTight);
      }
    }
  }
}

// A 20 x 20 cloth pinned at two corners: every level shrinks, keeps both
// pins kinematic, gives every movable child parents of its own level with
// weights summing to 1, and no coarse edge is shorter than the straight
// distance between its ends in the flat rest pose (the pass never pulls
// the cloth tighter than its edges allow).
TEST(Hierarchy, ClothLevelsKeepPinsWeightsAndRestBounds) {
  xpbd::SceneDesc s;
  xpbd::ClothGridDesc d;
  d.nx = d.ny = 20;
  d.pins = xpbd::ClothPins::top_corners;
  const xpbd::ClothGrid g = xpbd::add_cloth_grid(s, d);
  const xpbd::Model model = xpbd::compile(s);
  const auto h = xpbd::detail::build_hierarchy(model);
  ASSERT_GE(h->levels.size(), 2u);
  std::size_t finer = 400;
  for (std::size_t k = 0; k < h->levels.size(); ++k) {
    const auto& lev = h->levels[k];
    EXPECT_LT(Real(lev.particles.size()), Real(0.9) * Real(finer)) << "level " << k + 1;
    EXPECT_GE(lev.particles.size(), 8u);
    const std::set<Index> here(lev.particles.begin(), lev.particles.end());
    for (Index pin : g.pinned) {
      const auto it = std::find(lev.particles.begin(), lev.particles.end(), pin);
      ASSERT_NE(it, lev.particles.end()) << "pin " << pin << " level " << k + 1;
      EXPECT_EQ(lev.inv_mass[static_cast<std::size_t>(it - lev.particles.begin())], 0);
    }
    // Every particle of the finer level is here or a child (no pin is a child).
    EXPECT_EQ(lev.child.size() + lev.particles.size(), finer) << "level " << k + 1;
    for (std::size_t c = 0; c < lev.child.size(); ++c) {
      EXPECT_EQ(here.count(lev.child[c]), 0u);
      Real sum = 0;
      for (Index j = lev.parent_begin[c]; j < lev.parent_begin[c + 1]; ++j) {
        EXPECT_EQ(here.count(lev.parent[static_cast<std::size_t>(j)]), 1u);
        sum += lev.weight[static_cast<std::size_t>(j)];
      }
      EXPECT_NEAR(sum, 1, kTight);
    }
    for (std::size_t e = 0; e < lev.edges.size(); ++e) {
      const Vec3 a = model.x0[static_cast<std::size_t>(lev.particles[static_cast<std::size_t>(lev.edges[e][0])])];
      const Vec3 b = model.x0[static_cast<std::size_t>(lev.particles[static_cast<std::size_t>(lev.edges[e][1])])];
      EXPECT_GE(lev.rest[e], (a - b).norm() * (1 - kTight));
    }
    finer = lev.particles.size();
  }
}

// A fan: a ring of 2,000 particles, each joined to the next and to a hub
// listed last, so the greedy set takes every other ring particle and the
// hub is a child of 1,000 of them. It keeps the 16 nearest by rest length,
// so its coarse edges are at most 16 * 15 / 2 = 120 on top of the ring's,
// not half a million.
TEST(Hierarchy, AHubKeepsSixteenParents) {
  const int n = 2000;
  xpbd::SceneDesc s;
  for (int i = 0; i < n; ++i) {
    const Real a = Real(2) * std::numbers::pi_v<Real> * Real(i) / Real(n);
    s.add_particle(Vec3(std::cos(a), std::sin(a), 0), Real(0.01), 0);
  }
  s.add_particle(Vec3::Zero(), Real(0.01), 0);
  for (int i = 0; i < n; ++i) {
    s.distances.push_back({i, (i + 1) % n, std::nullopt, {}});
    s.distances.push_back({i, n, std::nullopt, {}});
  }
  const xpbd::Model model = xpbd::compile(s);
  const auto h = xpbd::detail::build_hierarchy(model);
  ASSERT_GE(h->levels.size(), 1u);
  const auto& lev = h->levels[0];
  ASSERT_EQ(lev.particles.size(), static_cast<std::size_t>(n / 2));
  const auto hub = std::find(lev.child.begin(), lev.child.end(), Index(n));
  ASSERT_NE(hub, lev.child.end());
  const std::size_t k = static_cast<std::size_t>(hub - lev.child.begin());
  EXPECT_EQ(lev.parent_begin[k + 1] - lev.parent_begin[k], 16);
  // The ring's coarse edges (n / 2, one per ring child) and the hub's 120,
  // some of which are ring edges already.
  EXPECT_LE(lev.edges.size(), static_cast<std::size_t>(n / 2 + 120));
  EXPECT_GE(lev.edges.size(), static_cast<std::size_t>(n / 2));
}

Real max_strain(const xpbd::Model& m, const xpbd::State& s) { return xpbd::distance_strain(m, s).max; }

// A stiff rope hanging from its pin, released straight: at 200 substeps per
// step every edge stays within the 1 % slack, so the pass moves nothing and
// the run is the plain run bit for bit.
TEST(Hierarchy, BelowTheSlackTheStepIsThePlainStep) {
  const xpbd::Model model = xpbd::compile(rope(33, Real(0.01), Real(0.002), Real(1e-6)));
  xpbd::State plain = xpbd::make_state(model), hier = plain;
  xpbd::StepConfig cfg;
  cfg.substeps = 200;
  xpbd::StepConfig with = cfg;
  with.hierarchy = true;
  for (int f = 0; f < 30; ++f) {
    xpbd::step(model, plain, cfg);
    xpbd::step(model, hier, with);
    ASSERT_LT(max_strain(model, plain), with.hierarchy_slack) << "frame " << f;
    for (std::size_t i = 0; i < plain.x.size(); ++i) ASSERT_EQ(plain.x[i], hier.x[i]) << "frame " << f << " particle " << i;
  }
  ASSERT_NE(hier.hierarchy, nullptr);
  EXPECT_EQ(hier.hierarchy->levels.size(), 2u);
}

// A light stiff rope of 129 particles with gravity, one sweep per substep
// at 10 substeps: the sweep leaves it far longer than its compliance says
// (the static stretch of link k is compliance * (n - 1 - k) m g, below
// 1e-5 here); the pass holds every coarse edge to its slack, so the fine
// edges' strain falls to the order of the slack.
TEST(Hierarchy, TheCoarseLevelsRemoveAStiffRopesStretch) {
  const int n = 129;
  const Real l = Real(0.01), m = Real(0.001), alpha = Real(1e-8);
  const xpbd::Model model = xpbd::compile(rope(n, l, m, alpha));
  xpbd::State plain = xpbd::make_state(model), hier = plain;
  xpbd::StepConfig cfg;
  cfg.drag = 2;
  xpbd::StepConfig with = cfg;
  with.hierarchy = true;
  for (int f = 0; f < 120; ++f) {
    xpbd::step(model, plain, cfg);
    xpbd::step(model, hier, with);
  }
  const auto sp = xpbd::distance_strain(model, plain), sh = xpbd::distance_strain(model, hier);
  ASSERT_LT(alpha * Real(n - 1) * m * Real(9.81) / l, Real(1e-5));  // the elastic strain
  EXPECT_GT(sp.mean, 10 * with.hierarchy_slack);
  EXPECT_LT(sh.max, Real(1.5) * with.hierarchy_slack);
}

TEST(Hierarchy, SlackMustBeFiniteAndNonNegative) {
  const xpbd::Model model = xpbd::compile(rope(5, Real(0.01), Real(0.002), 0));
  xpbd::State s = xpbd::make_state(model);
  xpbd::StepConfig cfg;
  cfg.hierarchy = true;
  for (Real bad : {Real(-0.01), std::numeric_limits<Real>::quiet_NaN(), std::numeric_limits<Real>::infinity()}) {
    cfg.hierarchy_slack = bad;
    try {
      xpbd::step(model, s, cfg);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const xpbd::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("StepConfig.hierarchy_slack"), std::string::npos) << e.what();
    }
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
