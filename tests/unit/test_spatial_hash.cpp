// Spatial hash and the self-collision pair search (spatial_hash.hpp).
//
// References are computed independently of the hash: brute-force O(n^2)
// loops over all pairs with the documented predicate |x_i - x_j|^2 < r^2,
// and connectivity read from the SceneDesc the test built.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "support/xpbd_test.hpp"
#include "xpbd/spatial_hash.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using Pair = std::pair<Index, Index>;

std::vector<Pair> brute_force(const std::vector<Vec3>& x, Real r) {
  std::vector<Pair> out;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j)
      if ((x[i] - x[j]).squaredNorm() < r * r) out.emplace_back(Index(i), Index(j));
  return out;
}

// The hash's pairs in visiting order (not sorted), to check for duplicates.
std::vector<Pair> hashed(const std::vector<Vec3>& x, Real cell, Real r) {
  SpatialHash h;
  build_spatial_hash(h, x, cell);
  std::vector<Pair> out;
  for_each_close_pair(h, std::span<const Vec3>(x), r, [&](Index i, Index j) { out.emplace_back(i, j); });
  return out;
}

void expect_same_pairs(const std::vector<Vec3>& x, Real cell, Real r, const char* what) {
  std::vector<Pair> got = hashed(x, cell, r);
  for (const Pair& p : got) ASSERT_LT(p.first, p.second) << what;
  std::sort(got.begin(), got.end());
  ASSERT_TRUE(std::adjacent_find(got.begin(), got.end()) == got.end())
      << what << ": a pair was reported twice (cell " << cell << ")";
  const std::vector<Pair> ref = brute_force(x, r);
  EXPECT_EQ(got, ref) << what << ": cell " << cell << " m, r " << r << " m";
}

TEST(SpatialHash, RandomCloudsMatchBruteForce) {
  const Real r = Real(0.3);  // m
  // Cell sizes below, at and above the query radius (1 to 13 cells per axis
  // in the query box), and a cell much larger than the cloud (one cell).
  const Real cells[] = {Real(0.05), Real(0.1), Real(0.3), Real(0.31), Real(1), Real(2.5), Real(100)};
  std::size_t total = 0;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<Real> u(Real(-1.5), Real(1.5));  // negative coordinates
    for (const Real cell : cells) {
      std::vector<Vec3> x;
      for (int k = 0; k < 300; ++k) x.emplace_back(u(rng), u(rng), u(rng));
      // Points exactly on cell borders: integer multiples of the cell size,
      // negative ones included, and one on a border on every axis.
      std::uniform_int_distribution<int> ki(-6, 6);
      for (int k = 0; k < 100; ++k)
        x.emplace_back(Real(ki(rng)) * cell * Real(0.25), Real(ki(rng)) * cell * Real(0.25), u(rng));
      for (int k = 0; k < 30; ++k) x.emplace_back(Real(ki(rng)) * cell, Real(ki(rng)) * cell, Real(ki(rng)) * cell);
      // Coincident points (distance 0 < r) and a far outlier.
      x.push_back(x[3]);
      x.push_back(x[3]);
      x.emplace_back(Real(1e6), Real(-1e6), 0);
      expect_same_pairs(x, cell, r, "random cloud");
      total += brute_force(x, r).size();
    }
  }
  // The clouds are dense enough that the comparison means something.
  EXPECT_GT(total, std::size_t(20000));
}

TEST(SpatialHash, LatticeAtExactlyTheRadius) {
  // A 9 x 9 x 5 lattice of spacing 0.25 m (exact in binary, so every
  // difference and square below is exact). With r = spacing, axis neighbours
  // sit at exactly r: not a pair (strict <), and nothing is closer, so there
  // are no pairs at all. With r slightly above the spacing, every axis
  // neighbour is a pair (diagonals at r sqrt(2) are not):
  // 8*9*5 + 9*8*5 + 9*9*4 = 1044 pairs. Every point lies on cell borders.
  const std::pair<Real, std::size_t> cases[] = {{Real(0.25), 0}, {Real(0.2500001), 1044}};
  for (const auto& [r, count] : cases) {
    std::vector<Vec3> x;
    for (int i = -4; i <= 4; ++i)
      for (int j = -4; j <= 4; ++j)
        for (int k = -2; k <= 2; ++k)
          x.emplace_back(Real(i) * Real(0.25), Real(j) * Real(0.25), Real(k) * Real(0.25));
    EXPECT_EQ(brute_force(x, r).size(), count);
    expect_same_pairs(x, Real(0.25), r, "lattice");
    expect_same_pairs(x, r, r, "lattice, cell = r");
    expect_same_pairs(x, Real(0.125), r, "lattice, cell = spacing / 2");
  }
}

TEST(SpatialHash, NonFinitePointIsNeverAPair) {
  std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(Real(0.1), 0, 0),
                         Vec3(std::numeric_limits<Real>::quiet_NaN(), 0, 0),
                         Vec3(std::numeric_limits<Real>::infinity(), 0, 0), Vec3(0, Real(0.1), 0)};
  const std::vector<Pair> ref = {{0, 1}, {0, 4}, {1, 4}};
  std::vector<Pair> got = hashed(x, Real(0.2), Real(0.2));
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, ref);
  EXPECT_EQ(brute_force(x, Real(0.2)), ref);
}

// cell_at against its definition: std::floor of x / cell (as x * inv_cell),
// clamped to [-2^30, 2^30], NaN to -2^30. Integers, their neighbours on
// both sides, -0, values past the clamp, infinities, NaN, and random values.
TEST(SpatialHash, CellIsTheClampedFloor) {
  const auto reference = [](Real v) {
    const Real f = std::floor(v);
    const Real lim = detail::kMaxCell;
    return static_cast<std::int32_t>(!(f >= -lim) ? -lim : (f > lim ? lim : f));
  };
  std::vector<Real> values = {Real(0), -Real(0), Real(0.5), Real(-0.5), Real(1e-30), Real(-1e-30),
                              detail::kMaxCell, -detail::kMaxCell, Real(2) * detail::kMaxCell,
                              -Real(2) * detail::kMaxCell, Real(1e30), Real(-1e30),
                              std::numeric_limits<Real>::infinity(), -std::numeric_limits<Real>::infinity(),
                              std::numeric_limits<Real>::quiet_NaN(), std::numeric_limits<Real>::max(),
                              std::numeric_limits<Real>::lowest(), std::numeric_limits<Real>::denorm_min(),
                              -std::numeric_limits<Real>::denorm_min()};
  for (const Real k : {Real(1), Real(2), Real(3), Real(1000), Real(1 << 23), Real(1 << 24), Real(1 << 29),
                       detail::kMaxCell - 1})
    for (const Real s : {Real(1), Real(-1)}) {
      values.push_back(s * k);
      values.push_back(std::nextafter(s * k, Real(0)));
      values.push_back(std::nextafter(s * k, s * std::numeric_limits<Real>::infinity()));
    }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1e4, 1e4);
  for (int i = 0; i < 2000; ++i) values.push_back(Real(u(rng)));
  for (const Real v : values)
    for (const Real inv_cell : {Real(1), Real(0.37), Real(8)}) {
      const Cell c = detail::cell_at(Vec3(v, -v, v * Real(0.5)), inv_cell);
      EXPECT_EQ(c[0], reference(v * inv_cell)) << "x = " << v << ", inv_cell = " << inv_cell;
      EXPECT_EQ(c[1], reference(-v * inv_cell)) << "x = " << -v << ", inv_cell = " << inv_cell;
      EXPECT_EQ(c[2], reference((v * Real(0.5)) * inv_cell)) << "x = " << v * Real(0.5) << ", inv_cell = " << inv_cell;
    }
}

// ---------------------------------------------------------------------------
// The self-collision stage

struct ClothScene {
  SceneDesc sd;
  ClothGrid grid;
};

// 6 x 6 cloth, spacing 0.1 m, top edge pinned (kinematic), one explicit
// collision pair. Contact distance 0.25 m: 2.5 spacings, so both connected
// and unconnected particles are within it.
ClothScene cloth_scene(bool hinges, bool skip_connected) {
  ClothScene c;
  ClothGridDesc g;
  g.nx = g.ny = 6;
  g.size_u = g.size_v = Real(0.5);
  g.radius = Real(0.01);
  g.pins = ClothPins::top_edge;
  if (hinges) {
    g.shear_both_diagonals = false;
    g.bend_distance = false;
    g.hinge_bending = HingeBending::dihedral;
  }
  c.grid = add_cloth_grid(c.sd, g);
  c.sd.collisions.push_back(CollisionDesc{c.grid.at(1, 1), c.grid.at(3, 2), {}});
  c.sd.self_collision.enabled = true;
  c.sd.self_collision.distance = Real(0.25);
  c.sd.self_collision.skip_connected = skip_connected;
  c.sd.self_collision.mat = Material{Real(1e-6), 0, 1};
  return c;
}

// Expected pairs from the scene description alone.
std::vector<Pair> expected_pairs(const SceneDesc& sd, Real r) {
  std::set<Pair> excluded;
  auto add = [&](Index a, Index b) { excluded.insert({std::min(a, b), std::max(a, b)}); };
  for (const auto& c : sd.collisions) add(c.a, c.b);
  if (sd.self_collision.skip_connected) {
    for (const auto& d : sd.distances) add(d.a, d.b);
    for (const auto& h : sd.dihedral_bends)
      for (int u = 0; u < 4; ++u)
        for (int v = u + 1; v < 4; ++v) add(h.p[std::size_t(u)], h.p[std::size_t(v)]);
  }
  std::vector<Pair> out;
  for (const Pair& p : brute_force(sd.positions, r)) {
    if (sd.masses[std::size_t(p.first)] == 0 && sd.masses[std::size_t(p.second)] == 0) continue;
    if (excluded.count(p)) continue;
    out.push_back(p);
  }
  return out;
}

std::vector<Pair> state_pairs(const State& s) {
  std::vector<Pair> out;
  for (const Collision& c : s.self_collision.pairs) out.emplace_back(c.p[0], c.p[1]);
  return out;
}

TEST(SelfCollision, PairsAreCloseUnconnectedAndSorted) {
  for (const bool hinges : {false, true})
    for (const bool skip : {true, false}) {
      const ClothScene c = cloth_scene(hinges, skip);
      const Model m = compile(c.sd);
      State s = make_state(m);
      StepConfig cfg;
      cfg.gravity.setZero();  // at rest: travel 0, query radius = d
      find_self_collisions(m, s, cfg);
      EXPECT_EQ(s.self_collision.radius, Real(0.25));
      const std::vector<Pair> ref = expected_pairs(c.sd, Real(0.25));
      const std::vector<Pair> got = state_pairs(s);  // order as stored: must already be sorted
      EXPECT_EQ(got, ref) << "hinges " << hinges << ", skip_connected " << skip;
      EXPECT_TRUE(std::is_sorted(got.begin(), got.end()));
      ASSERT_EQ(s.self_collision.lambda.size(), got.size());
      for (const Collision& p : s.self_collision.pairs) {
        EXPECT_EQ(p.rest, Real(0.25));
        EXPECT_EQ(p.mat.compliance, Real(1e-6));
      }
      // Non-trivial: pairs found, and with skip_connected some close pairs
      // (all edges at 0.1 m) were dropped.
      EXPECT_GT(got.size(), std::size_t(20));
      if (skip) {
        const SceneDesc& sd = c.sd;
        std::size_t close_edges = 0;
        for (const auto& d : sd.distances)
          close_edges += (sd.positions[std::size_t(d.a)] - sd.positions[std::size_t(d.b)]).norm() < Real(0.25);
        EXPECT_GT(close_edges, std::size_t(0));
        for (const auto& d : sd.distances)
          EXPECT_FALSE(std::binary_search(got.begin(), got.end(),
                                          Pair{std::min(d.a, d.b), std::max(d.a, d.b)}));
      }
    }
}

TEST(SelfCollision, QueryRadiusCoversTheStepsTravel) {
  // Gravity 9.81 m/s^2, dt = 1/60 s. Particle 0 moves at 3 m/s:
  // t_0 = 3 dt + g dt^2; the others are at rest: t = g dt^2. Hash radius
  // r = d + 2 t_0; a pair is a candidate if closer than d + t_i + t_j.
  // Particle 1 sits just inside d + t_0 + t_1 from particle 0, particle 2
  // just outside it (but inside r, so only the per-pair bound rejects it).
  const Real d = Real(0.1), dt = Real(1) / Real(60), g = Real(9.81);
  const Real t0 = 3 * dt + g * dt * dt, t_rest = g * dt * dt;
  {
    SceneDesc sd;
    sd.add_particle(Vec3::Zero(), 1, 0, Vec3(3, 0, 0));
    const Real r01 = d + t0 + t_rest;
    sd.add_particle(Vec3(0, r01 * Real(0.999), 0), 1);
    sd.add_particle(Vec3(0, 0, -r01 * Real(1.001)), 1);
    ASSERT_LT(r01 * Real(1.001), d + 2 * t0);
    sd.self_collision.enabled = true;
    sd.self_collision.distance = d;
    const Model m = compile(sd);
    State s = make_state(m);
    StepConfig cfg;
    cfg.gravity = Vec3(0, -g, 0);
    find_self_collisions(m, s, cfg);
    EXPECT_NEAR(s.self_collision.radius, d + 2 * t0, 4 * test::kEps);
    EXPECT_NEAR(s.self_collision.travel[0], t0, 4 * test::kEps);
    EXPECT_NEAR(s.self_collision.travel[1], t_rest, 4 * test::kEps);
    EXPECT_EQ(state_pairs(s), (std::vector<Pair>{{0, 1}}));
  }
  {
    // Particle 0 is kinematic with a pin whose target moves 0.2 m this step:
    // t_0 = 0.2 m.
    SceneDesc sd;
    sd.add_particle(Vec3::Zero(), 0);
    sd.pins.push_back(PinDesc{0, std::nullopt, {}});
    sd.add_particle(Vec3(Real(0.299), 0, 0), 1);   // inside d + 0.2 + t_rest
    sd.add_particle(Vec3(Real(-0.31), 0, 0), 1);   // outside
    sd.self_collision.enabled = true;
    sd.self_collision.distance = d;
    const Model m = compile(sd);
    State s = make_state(m);
    s.pin_target[0] = Vec3(0, Real(0.2), 0);
    StepConfig cfg;
    cfg.gravity = Vec3(0, -g, 0);
    find_self_collisions(m, s, cfg);
    EXPECT_NEAR(s.self_collision.radius, d + 2 * Real(0.2), 4 * test::kEps);
    EXPECT_EQ(state_pairs(s), (std::vector<Pair>{{0, 1}}));
  }
}

TEST(SelfCollision, KinematicPairsAreSkipped) {
  SceneDesc sd;
  sd.add_particle(Vec3::Zero(), 0);
  sd.add_particle(Vec3(Real(0.05), 0, 0), 0);
  sd.add_particle(Vec3(0, Real(0.05), 0), 2);
  sd.self_collision.enabled = true;
  sd.self_collision.distance = Real(0.1);
  const Model m = compile(sd);
  State s = make_state(m);
  StepConfig cfg;
  cfg.gravity.setZero();
  find_self_collisions(m, s, cfg);
  EXPECT_EQ(state_pairs(s), (std::vector<Pair>{{0, 2}, {1, 2}}));
}

TEST(SelfCollision, OffMeansNoArraysAndNoPairs) {
  SceneDesc sd;
  ClothGridDesc g;
  g.nx = g.ny = 8;
  add_cloth_grid(sd, g);  // particles 1/7 m apart, overlapping any d
  const Model m = compile(sd);
  EXPECT_FALSE(m.self_collision.enabled);
  EXPECT_EQ(m.self_collision.exclude_begin.capacity(), 0u);
  EXPECT_EQ(m.self_collision.exclude.capacity(), 0u);
  State s = make_state(m);
  for (int k = 0; k < 5; ++k) step(m, s, StepConfig{});
  const SelfCollisionState& sc = s.self_collision;
  EXPECT_EQ(sc.pairs.capacity(), 0u);
  EXPECT_EQ(sc.lambda.capacity(), 0u);
  EXPECT_EQ(sc.hash.cell_of.capacity(), 0u);
  EXPECT_EQ(sc.hash.bucket_begin.capacity(), 0u);
  EXPECT_EQ(sc.hash.sorted.capacity(), 0u);
  EXPECT_EQ(sc.radius, Real(0));
}

TEST(SelfCollision, BadInputIsNamed) {
  SceneDesc sd;
  sd.add_particle(Vec3::Zero(), 1);
  sd.self_collision.distance = -1;  // ignored while disabled
  EXPECT_NO_THROW((void)compile(sd));
  sd.self_collision.enabled = true;
  EXPECT_TRUE(test::scene_error_names(sd, {"self_collision.distance", "-1"}));
  sd.self_collision.distance = 0;
  EXPECT_TRUE(test::scene_error_names(sd, {"self_collision.distance", "0"}));
  sd.self_collision.distance = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_TRUE(test::scene_error_names(sd, {"self_collision.distance", "nan"}));
  sd.self_collision.distance = std::numeric_limits<Real>::infinity();
  EXPECT_TRUE(test::scene_error_names(sd, {"self_collision.distance", "inf"}));
  sd.self_collision.distance = Real(0.1);
  sd.self_collision.mat.compliance = -2;
  EXPECT_TRUE(test::scene_error_names(sd, {"self_collision.mat.compliance", "-2"}));

  // A non-finite velocity: the travel cannot be bounded.
  sd.self_collision.mat.compliance = 0;
  sd.add_particle(Vec3(1, 0, 0), 1);
  const Model m = compile(sd);
  State s = make_state(m);
  s.v[1] = Vec3(std::numeric_limits<Real>::infinity(), 0, 0);
  const std::vector<Vec3> v_last = s.self_collision.v_last;
  EXPECT_TRUE(test::config_error_names(m, s, StepConfig{}, {"state.v[1]", "not finite"}));
  EXPECT_EQ(s.self_collision.v_last, v_last);  // nothing changed by the failed step
  s.v[1].setZero();

  // A kinematic pinned particle whose target is not finite.
  sd.add_particle(Vec3(2, 0, 0), 0);
  sd.pins.push_back(PinDesc{2, std::nullopt, {}});
  const Model m2 = compile(sd);
  State s2 = make_state(m2);
  s2.pin_target[0] = Vec3(std::numeric_limits<Real>::quiet_NaN(), 0, 0);
  EXPECT_TRUE(test::config_error_names(m2, s2, StepConfig{}, {"state.pin_target[0]", "not finite"}));
}

TEST(SelfCollision, NoReallocationOnceSized) {
  // A cloth falling onto a pinned one: the pair count changes from step to
  // step. The hash arrays keep their storage; the pair arrays move only when
  // a step needs more than their capacity.
  SceneDesc sd;
  ClothGridDesc lo;
  lo.nx = lo.ny = 10;
  lo.v = Vec3::UnitZ();
  lo.pins = ClothPins::all_corners;
  add_cloth_grid(sd, lo);
  ClothGridDesc up = lo;
  up.pins = ClothPins::none;
  up.origin = Vec3(Real(0.05), Real(0.1), Real(0.05));
  add_cloth_grid(sd, up);
  sd.self_collision.enabled = true;
  sd.self_collision.distance = Real(0.08);
  const Model m = compile(sd);
  State s = make_state(m);
  const SelfCollisionState& sc = s.self_collision;
  const void* cell_of = sc.hash.cell_of.data();
  const void* buckets = sc.hash.bucket_begin.data();
  const void* sorted = sc.hash.sorted.data();
  std::size_t max_pairs = 0;
  for (int k = 0; k < 60; ++k) {
    const void* pairs = sc.pairs.data();
    const std::size_t cap = sc.pairs.capacity();
    step(m, s, StepConfig{});
    EXPECT_EQ(sc.hash.cell_of.data(), cell_of);
    EXPECT_EQ(sc.hash.bucket_begin.data(), buckets);
    EXPECT_EQ(sc.hash.sorted.data(), sorted);
    if (sc.pairs.size() <= cap) {
      EXPECT_EQ(sc.pairs.data(), pairs) << "step " << k;
    }
    max_pairs = std::max(max_pairs, sc.pairs.size());
  }
  EXPECT_GT(max_pairs, std::size_t(0));
  EXPECT_TRUE(test::all_finite(s));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
