// Particle-particle collision (spatial_hash.hpp) keeping cloths apart:
//  - two 16 x 16 cloths, the lower one pinned at its four corners, the upper
//    one dropped onto it: they never pass through each other with collision
//    on, and they do with it off;
//  - one cloth pinned along its middle row: its two halves fall and hang
//    side by side, kept apart by self-collision within the one cloth, and
//    swing through each other without it.
//
// Tolerance. At the end of every step every unconnected pair (i, j) must be
// at least d - tol_ij apart, tol_ij = (|v_i - v_j| + g dt) h, with the
// velocities of the step's start, dt the step and h the substep:
//  - the contacts are projected last in every iteration and each projection
//    leaves its own pair exactly at C = 0 (zero compliance); the share of the
//    overlap left at the end of a substep comes from later projections in
//    the same sweep pulling a particle of the pair back, which moves it by
//    less than the overlap that substep created;
//  - the overlap one substep can create is the pair's relative travel in
//    it: its relative speed, at most |v_i - v_j| at the step start plus what
//    gravity adds over the step (g dt), times h.
// This is a scale rather than a strict bound (constraint forces also change
// velocities within a step). Measured (double, 1 iteration): worst
// violation / tol_ij = 0.06 for the two cloths (closest pair 0.05977 m for
// d = 0.06 m, at the impact); the folded cloth keeps every pair at d to
// 1e-9 m. Without collision the ratio reaches 5 (two cloths) and 85 (fold).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <utility>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

constexpr int kN = 16;                           // particles per side
constexpr Real kSize = 1;                        // m
constexpr Real kSpacing = kSize / Real(kN - 1);  // m, 1/15
// Contact distance between particle centres, m. Above kSpacing/sqrt(2), the
// distance from the centre of a grid square to its corners, so that a
// particle cannot slip through the middle of a square of the other cloth;
// below the closest unconnected distance within a flat cloth (sqrt(5)
// spacings with bend-distance edges, 2 spacings without), so a flat cloth
// has no self-contacts at rest.
constexpr Real kDist = Real(0.9) * kSpacing;
constexpr Real kG = Real(9.81);  // m/s^2

struct RunStats {
  Real worst_ratio = 0;      // max over steps and pairs of (d - |x_i - x_j|) / tol_ij
  Real min_cross = 1e9;      // m, closest pair from different groups, over the run
  Real min_within = 1e9;     // m, closest unconnected pair within one group
  std::size_t max_pairs = 0; // most candidate pairs in a step
  std::size_t last_pairs = 0;
  int contact_steps = 0;     // steps with at least one pushing pair (lambda > 0)
};

// Steps the scene `steps` times and measures every unconnected pair after
// every step. group[i] tells which cloth particle i belongs to.
RunStats simulate(const SceneDesc& sd, const std::vector<int>& group, int steps, State* out = nullptr) {
  const Model m = compile(sd);
  State s = make_state(m);
  StepConfig cfg;  // 60 Hz, 10 substeps, 1 iteration, g = 9.81 m/s^2 down
  const Real h = cfg.dt / Real(cfg.substeps);
  const Real d = sd.self_collision.enabled ? sd.self_collision.distance : kDist;

  // Connected pairs, from the scene description (the exclusions compile()
  // derives for skip_connected, here only distance edges).
  std::set<std::pair<Index, Index>> connected;
  for (const auto& e : sd.distances) connected.insert({std::min(e.a, e.b), std::max(e.a, e.b)});
  const Index n = m.num_particles();

  RunStats r;
  for (int k = 0; k < steps; ++k) {
    const std::vector<Vec3> v0 = s.v;
    step(m, s, cfg);
    r.max_pairs = std::max(r.max_pairs, s.self_collision.pairs.size());
    bool pushing = false;
    for (Real l : s.self_collision.lambda) pushing = pushing || l > 0;
    r.contact_steps += pushing;
    for (Index i = 0; i < n; ++i)
      for (Index j = i + 1; j < n; ++j) {
        if (connected.count({i, j})) continue;
        const Real dist = (s.x[i] - s.x[j]).norm();
        if (group[std::size_t(i)] != group[std::size_t(j)])
          r.min_cross = std::min(r.min_cross, dist);
        else
          r.min_within = std::min(r.min_within, dist);
        const Real tol = ((v0[i] - v0[j]).norm() + kG * cfg.dt) * h;
        r.worst_ratio = std::max(r.worst_ratio, (d - dist) / tol);
      }
  }
  EXPECT_TRUE(test::all_finite(s));
  r.last_pairs = s.self_collision.pairs.size();
  if (out) *out = s;
  return r;
}

// Lower cloth in the plane y = 0 over [0, 1] x [0, 1] (x, z), pinned at its
// corners; upper cloth 0.2 m above, shifted by half a spacing in x and z so
// that each of its particles falls onto the centre of a lower square (the
// easiest place to slip through).
struct TwoCloths {
  SceneDesc sd;
  ClothGrid lower, upper;
  std::vector<int> group;
};

TwoCloths two_cloths(bool collide) {
  TwoCloths t;
  ClothGridDesc lo;
  lo.nx = lo.ny = kN;
  lo.size_u = lo.size_v = kSize;
  lo.u = Vec3::UnitX();
  lo.v = Vec3::UnitZ();
  lo.pins = ClothPins::all_corners;
  lo.mass = 1;  // kg
  t.lower = add_cloth_grid(t.sd, lo);
  ClothGridDesc up = lo;
  up.pins = ClothPins::none;
  up.origin = Vec3(kSpacing / 2, Real(0.2), kSpacing / 2);
  t.upper = add_cloth_grid(t.sd, up);
  t.sd.self_collision.enabled = collide;
  t.sd.self_collision.distance = kDist;
  t.group.assign(std::size_t(t.sd.num_particles()), 0);
  std::fill(t.group.begin() + t.upper.first, t.group.end(), 1);
  return t;
}

TEST(ParticleCollisionCloth, FallingClothStaysOnPinnedCloth) {
  TwoCloths t = two_cloths(true);
  State s;
  const RunStats r = simulate(t.sd, t.group, 120, &s);  // 2 s
  std::printf("two cloths, collision on: min distance %.6f m across, %.6f m within "
              "(d = %.6f m), worst violation / tol %.4f, pairs max %zu, last %zu\n",
              double(r.min_cross), double(r.min_within), double(kDist), double(r.worst_ratio),
              r.max_pairs, r.last_pairs);
  EXPECT_LE(r.worst_ratio, Real(1));
  EXPECT_GT(r.contact_steps, 60);  // the cloths did meet and rest on each other
  // The upper cloth ends above the lower one: its centre particle is above
  // the lower centre particle by about the contact distance (it sits in a
  // square of four lower particles: height d*sqrt(1 - 1/(2*0.81)) = 0.62 d
  // for a flat square; the bowl tilts and stretches it, so only ask for
  // above by half of that).
  const Real up_c = s.x[t.upper.at(kN / 2, kN / 2)].y();
  const Real lo_c = s.x[t.lower.at(kN / 2, kN / 2)].y();
  EXPECT_GT(up_c - lo_c, Real(0.3) * kDist) << "upper centre " << up_c << ", lower " << lo_c;
}

TEST(ParticleCollisionCloth, WithoutCollisionTheClothFallsThrough) {
  TwoCloths t = two_cloths(false);
  State s;
  const RunStats r = simulate(t.sd, t.group, 120, &s);
  std::printf("two cloths, collision off: min distance across %.6f m, worst ratio %.3f\n",
              double(r.min_cross), double(r.worst_ratio));
  EXPECT_GT(r.worst_ratio, Real(1));  // the check above would have failed
  EXPECT_EQ(s.self_collision.pairs.size(), 0u);
  // After 2 s the upper cloth is in free fall far below: every upper
  // particle is below every lower one.
  Real upper_top = -1e9, lower_bottom = 1e9;
  for (Index i = 0; i < t.sd.num_particles(); ++i) {
    if (t.group[std::size_t(i)] == 1)
      upper_top = std::max(upper_top, s.x[i].y());
    else
      lower_bottom = std::min(lower_bottom, s.x[i].y());
  }
  EXPECT_LT(upper_top, lower_bottom);
}

// One cloth in the plane y = 0, pinned along its middle row j = 7, without
// bend-distance edges (they would hold the fold line straight). Both halves
// swing down and meet face to face under the pinned row.
SceneDesc folding_cloth(bool collide) {
  SceneDesc sd;
  ClothGridDesc c;
  c.nx = c.ny = kN;
  c.size_u = c.size_v = kSize;
  c.u = Vec3::UnitX();
  c.v = Vec3::UnitZ();
  c.bend_distance = false;
  for (int i = 0; i < kN; ++i) c.pinned.emplace_back(i, 7);
  add_cloth_grid(sd, c);
  sd.self_collision.enabled = collide;
  sd.self_collision.distance = kDist;
  return sd;
}

TEST(ParticleCollisionCloth, FoldedClothKeepsItsHalvesApart) {
  const SceneDesc sd = folding_cloth(true);
  const std::vector<int> group(std::size_t(sd.num_particles()), 0);
  const RunStats r = simulate(sd, group, 120, nullptr);
  std::printf("folded cloth, collision on: min distance within %.9f m (d = %.6f m), worst "
              "violation / tol %.4f, pairs max %zu, last %zu\n",
              double(r.min_within), double(kDist), double(r.worst_ratio), r.max_pairs, r.last_pairs);
  EXPECT_LE(r.worst_ratio, Real(1));
  EXPECT_GT(r.contact_steps, 60);  // the halves did meet
}

TEST(ParticleCollisionCloth, WithoutCollisionTheHalvesPassThrough) {
  const SceneDesc sd = folding_cloth(false);
  const std::vector<int> group(std::size_t(sd.num_particles()), 0);
  const RunStats r = simulate(sd, group, 120, nullptr);
  std::printf("folded cloth, collision off: min distance within %.6f m, worst ratio %.3f\n",
              double(r.min_within), double(r.worst_ratio));
  EXPECT_GT(r.worst_ratio, Real(1));
  EXPECT_LT(r.min_within, kDist / 2);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
