// Array order's levels (Model::distance_levels and tether_levels,
// StepConfig::levels): XPBD's array-order Distance and Tether sweeps run
// level by level over a compiled stream with the vector kernel.
//
// Checked here:
//   - the schedule: a permutation of the elements, no two elements of a
//     level sharing a particle, array order within a level, and every
//     element on a higher level than each earlier element that shares a
//     particle with it (what makes the level order give the array order's
//     result); a rope's levels are its elements one by one;
//   - the result: a step over the levels equals the element-by-element
//     step bit for bit (positions, velocities, multipliers), undamped and
//     damped, at one and two iterations, with alternating sweeps, and after
//     set_material, and on a cloth tethered to its pins (the tethers'
//     levels share only the anchors); while the coloured order, a different
//     Gauss-Seidel order, differs (so the comparison can fail);
//   - where it applies (uses_levels): not on a rope, in PBD, with coloured,
//     simd or levels off, with direct_chains, nor on a Model whose levels do
//     not cover its elements (which still steps, element by element).
#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "support/xpbd_test.hpp"
#include "xpbd/distance_stream.hpp"
#include "xpbd/materials.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

Model cloth(int n, bool damped) {
  SceneDesc scene;
  ClothGridDesc d;
  d.nx = d.ny = n;
  d.size_u = d.size_v = 1;
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();  // horizontal: it falls and swings from two corners
  d.mass = 1;
  d.pinned = {{0, 0}, {n - 1, 0}};
  d.stretch.compliance = Real(1e-6);
  d.shear_mat.compliance = Real(1e-5);
  d.bend_mat.compliance = Real(1e-4);
  if (damped) d.stretch.damping = d.shear_mat.damping = d.bend_mat.damping = Real(10);
  add_cloth_grid(scene, d);
  return compile(scene);
}

// The cloth tethered to its two pins: a tether from every movable particle
// to each pin (the anchors, inverse mass 0, shared by every tether of a pin).
Model tethered_cloth(int n, bool damped) {
  SceneDesc scene;
  ClothGridDesc d;
  d.nx = d.ny = n;
  d.size_u = d.size_v = 1;
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  d.mass = 1;
  d.pinned = {{0, 0}, {n - 1, 0}};
  d.stretch.compliance = Real(1e-6);
  d.tethers = TetherAnchors::all_pinned;
  d.tether_metric = TetherMetric::euclidean;
  if (damped) d.stretch.damping = d.tether_mat.damping = Real(10);
  add_cloth_grid(scene, d);
  return compile(scene);
}

Model rope(int n) {
  SceneDesc scene;
  RopeDesc r;
  r.n = n;
  r.mat.compliance = Real(1e-6);
  add_rope(scene, r);
  return compile(scene);
}

Model tet_box() {
  SceneDesc scene;
  TetBoxDesc t;
  t.nx = t.ny = t.nz = 3;
  t.edge_mat.compliance = Real(1e-6);
  t.pinned = {{0, 0, 0}};
  add_tet_box(scene, t);
  return compile(scene);
}

// The level schedule's structure; returns the number of levels.
Index check_levels(const Model& m) {
  const auto& cs = m.get<Distance>();
  const ColourSchedule& l = m.distance_levels;
  EXPECT_EQ(l.order.size(), cs.size());
  EXPECT_EQ(m.distance_level_stream.size(), cs.size());
  if (l.begin.empty()) {
    ADD_FAILURE() << "no levels";
    return 0;
  }
  EXPECT_EQ(l.begin.front(), 0);
  EXPECT_EQ(static_cast<std::size_t>(l.begin.back()), cs.size());
  std::vector<Index> level_of(cs.size(), -1);
  for (Index c = 0; c < l.num_colours(); ++c) {
    const Index b = l.begin[std::size_t(c)], e = l.begin[std::size_t(c) + 1];
    EXPECT_LT(b, e) << "level " << c << " is empty";
    std::set<Index> particles;
    for (Index j = b; j < e; ++j) {
      const Index k = l.order[std::size_t(j)];
      if (!(k >= 0 && std::size_t(k) < cs.size())) {
        ADD_FAILURE() << "element " << k << " out of range";
        continue;
      }
      EXPECT_EQ(level_of[std::size_t(k)], -1) << "element " << k << " twice";
      level_of[std::size_t(k)] = c;
      const Distance& d = cs[std::size_t(k)];
      EXPECT_TRUE(particles.insert(d.p[0]).second) << "level " << c << " particle " << d.p[0];
      EXPECT_TRUE(particles.insert(d.p[1]).second) << "level " << c << " particle " << d.p[1];
      if (j > b) {
        EXPECT_LT(l.order[std::size_t(j) - 1], k);
      }
    }
  }
  // Every earlier element that shares a particle is on a lower level.
  std::vector<Index> last(std::size_t(m.num_particles()), -1);  // last element at each particle
  for (std::size_t k = 0; k < cs.size(); ++k) {
    for (Index p : cs[k].p) {
      const Index before = last[std::size_t(p)];
      if (before >= 0) {
        EXPECT_LT(level_of[std::size_t(before)], level_of[k]) << "elements " << before << ", " << k;
      }
    }
    for (Index p : cs[k].p) last[std::size_t(p)] = static_cast<Index>(k);
  }
  return l.num_colours();
}

TEST(DistanceLevels, ScheduleOfClothRopeAndTetBox) {
  const Model c = cloth(16, false);
  const Index cl = check_levels(c);
  EXPECT_GT(cl, 1);
  EXPECT_LT(cl, static_cast<Index>(c.get<Distance>().size()) / 4);  // wide levels: many elements each
  const Model r = rope(12);
  EXPECT_EQ(check_levels(r), static_cast<Index>(r.get<Distance>().size()));  // a chain: one element per level
  EXPECT_GT(check_levels(tet_box()), 1);
}

// The levels run only on a CPU with a vector kernel (uses_levels).
bool no_vector_kernel() { return std::string(simd_kernel()) == "scalar"; }

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}
bool same_bits(const std::vector<Real>& a, const std::vector<Real>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Real)) == 0;
}

// Steps `m` `steps` times from `from` with `on` (levels on) and with levels
// off, and asserts after every step that both give the same bits:
// positions, velocities, and the Distance and Tether multipliers. Returns
// the state stepped with the levels.
State expect_same_steps(const Model& m, const StepConfig& on, int steps, const State& from) {
  StepConfig off = on;
  off.levels = false;
  State a = from, b = from;
  for (int k = 0; k < steps; ++k) {
    step(m, a, on);
    step(m, b, off);
    EXPECT_TRUE(same_bits(a.x, b.x)) << "positions, step " << k;
    EXPECT_TRUE(same_bits(a.v, b.v)) << "velocities, step " << k;
    EXPECT_TRUE(same_bits(a.lambdas<Distance>(), b.lambdas<Distance>())) << "distance multipliers, step " << k;
    EXPECT_TRUE(same_bits(a.lambdas<Tether>(), b.lambdas<Tether>())) << "tether multipliers, step " << k;
    if (::testing::Test::HasFailure()) break;
  }
  return a;
}

// Steps `m` with the levels and element by element (and coloured), from the
// same state, and compares the results after every step.
void expect_array_order_bits(const Model& m, int iterations, bool alternate) {
  if (no_vector_kernel()) GTEST_SKIP() << "no vector kernel on this CPU: the levels do not run";
  StepConfig on;
  on.dt = Real(1) / 60;
  on.substeps = 10;
  on.iterations = iterations;
  on.alternate_sweeps = alternate;
  StepConfig off = on, coloured = on;
  off.levels = false;
  coloured.coloured = true;
  ASSERT_TRUE(uses_levels(m, on));
  ASSERT_FALSE(uses_levels(m, off));
  State a = make_state(m), b = make_state(m), c = make_state(m);
  for (int k = 0; k < 30; ++k) {
    step(m, a, on);
    step(m, b, off);
    step(m, c, coloured);
    ASSERT_TRUE(same_bits(a.x, b.x)) << "positions, step " << k;
    ASSERT_TRUE(same_bits(a.v, b.v)) << "velocities, step " << k;
    ASSERT_TRUE(same_bits(a.lambdas<Distance>(), b.lambdas<Distance>())) << "multipliers, step " << k;
  }
  ASSERT_TRUE(test::all_finite(a.x));
  Real moved = 0, differs = 0;
  for (std::size_t i = 0; i < a.x.size(); ++i) {
    moved = std::max(moved, (a.x[i] - m.x0[i]).norm());
    differs = std::max(differs, (a.x[i] - c.x[i]).norm());
  }
  EXPECT_GT(moved, Real(0.1));     // m: the cloth fell and swung
  EXPECT_GT(differs, Real(1e-4));  // m: another order does give another result
}

TEST(DistanceLevels, StepEqualsTheArrayOrderBitForBit) { expect_array_order_bits(cloth(24, false), 1, false); }
TEST(DistanceLevels, DampedStepEqualsTheArrayOrderBitForBit) { expect_array_order_bits(cloth(24, true), 1, false); }
TEST(DistanceLevels, TwoAlternatingIterationsEqualTheArrayOrderBitForBit) {
  expect_array_order_bits(cloth(24, true), 2, true);
}
// The Tether levels: no two elements of a level share a particle that
// moves, and each element is above every earlier element that shares a
// moving particle with it; the anchors (inverse mass 0) do not count.
TEST(DistanceLevels, TetherScheduleSharesOnlyAnchors) {
  const Model m = tethered_cloth(12, false);
  const auto& cs = m.get<Tether>();
  const ColourSchedule& l = m.tether_levels;
  ASSERT_EQ(l.order.size(), cs.size());
  ASSERT_EQ(m.tether_level_stream.size(), cs.size());
  ASSERT_FALSE(l.begin.empty());
  std::vector<Index> level_of(cs.size(), -1);
  for (Index c = 0; c < l.num_colours(); ++c) {
    std::set<Index> moving;
    for (Index j = l.begin[std::size_t(c)]; j < l.begin[std::size_t(c) + 1]; ++j) {
      const Index k = l.order[std::size_t(j)];
      level_of[std::size_t(k)] = c;
      for (Index p : cs[std::size_t(k)].p)
        if (m.inv_mass[std::size_t(p)] != Real(0)) {
          EXPECT_TRUE(moving.insert(p).second) << "level " << c;
        }
    }
  }
  std::vector<Index> last(std::size_t(m.num_particles()), -1);
  for (std::size_t k = 0; k < cs.size(); ++k) {
    for (Index p : cs[k].p) {
      if (m.inv_mass[std::size_t(p)] == Real(0) || last[std::size_t(p)] < 0) continue;
      EXPECT_LT(level_of[std::size_t(last[std::size_t(p)])], level_of[k]) << "elements " << last[std::size_t(p)]
                                                                             << ", " << k;
    }
    for (Index p : cs[k].p) last[std::size_t(p)] = static_cast<Index>(k);
  }
  EXPECT_LE(l.num_colours(), 4);  // two tethers per particle: the anchors shared by all do not add levels
}

// Positions, velocities and both types' multipliers, levels on and off.
void expect_tethered_bits(bool damped) {
  if (no_vector_kernel()) GTEST_SKIP() << "no vector kernel on this CPU: the levels do not run";
  const Model m = tethered_cloth(24, damped);
  StepConfig on;
  on.dt = Real(1) / 60;
  on.substeps = 10;
  ASSERT_TRUE(uses_levels(m, on));
  const State a = expect_same_steps(m, on, 30, make_state(m));
  Real pulled = 0;  // some tethers were taut
  for (Real l : a.lambdas<Tether>()) pulled = std::max(pulled, std::abs(l));
  EXPECT_GT(pulled, Real(0));
}

TEST(DistanceLevels, TetheredClothEqualsTheArrayOrderBitForBit) { expect_tethered_bits(false); }
TEST(DistanceLevels, DampedTetheredClothEqualsTheArrayOrderBitForBit) { expect_tethered_bits(true); }

TEST(DistanceLevels, TetBoxEqualsTheArrayOrderBitForBit) {
  if (no_vector_kernel()) GTEST_SKIP() << "no vector kernel on this CPU: the levels do not run";
  const Model m = tet_box();
  StepConfig on;
  on.dt = Real(1) / 60;
  ASSERT_TRUE(uses_levels(m, on));
  expect_same_steps(m, on, 30, make_state(m));
}

// set_material refreshes the level stream: the new compliance is what both
// kernels use.
TEST(DistanceLevels, FollowsSetMaterial) {
  if (no_vector_kernel()) GTEST_SKIP() << "no vector kernel on this CPU: the levels do not run";
  Model m = cloth(24, false);
  StepConfig on;
  on.dt = Real(1) / 60;
  State before = make_state(m);
  for (int k = 0; k < 10; ++k) step(m, before, on);
  set_material<Distance>(m, 0, m.get<Distance>().size() / 2, Material{Real(1e-2), Real(0.5), 1});
  const State a = expect_same_steps(m, on, 10, make_state(m));
  Real differs = 0;  // the soft half does stretch more than before the change
  for (std::size_t i = 0; i < a.x.size(); ++i) differs = std::max(differs, (a.x[i] - before.x[i]).norm());
  EXPECT_GT(differs, Real(1e-3));
}

TEST(DistanceLevels, WhereTheyApply) {
  const Model c = cloth(16, false);
  StepConfig cfg;
  EXPECT_EQ(uses_levels(c, cfg), !no_vector_kernel());
  EXPECT_FALSE(uses_levels(rope(40), cfg));  // one element per level: slower than element by element
  StepConfig pbd = cfg, coloured = cfg, scalar = cfg, off = cfg, chains = cfg;
  pbd.method = Method::pbd;
  coloured.coloured = true;
  scalar.simd = false;
  off.levels = false;
  chains.direct_chains = true;
  for (const StepConfig* k : {&pbd, &coloured, &scalar, &off, &chains}) EXPECT_FALSE(uses_levels(c, *k));
  // A Model whose levels do not cover its elements (edited after compile)
  // steps element by element.
  Model edited = c;
  edited.get<Distance>().pop_back();
  edited.distance_colours = {};
  EXPECT_FALSE(uses_levels(edited, cfg));
  State s = make_state(edited);
  for (int k = 0; k < 5; ++k) step(edited, s, cfg);
  EXPECT_TRUE(test::all_finite(s.x));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
