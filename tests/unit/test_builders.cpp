// Scene builders (xpbd/builders.hpp), the cloth grid: element counts against
// closed-form formulas, masses, pins, hinge layout, geodesic tether lengths,
// and error messages. Every expected value is computed here from the
// geometry, never from the builder. The tetrahedral box and triangle meshes
// are in test_builders_solids.cpp.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

using test::throws_naming;
using test::total_mass;

// ---------------------------------------------------------------------------
// Cloth grid

// Counts for an nx x ny grid (n = nx*ny particles, quads (nx-1)(ny-1)):
//   structural edges   (nx-1) ny + nx (ny-1) = 2 nx ny - nx - ny
//   shear, both diags  2 (nx-1)(ny-1); one diagonal: (nx-1)(ny-1)
//   bending distance   (nx-2) ny + nx (ny-2)
//   triangles          2 (nx-1)(ny-1)
//   interior edges     (nx-1)(ny-2) horizontal + (nx-2)(ny-1) vertical
//                      + (nx-1)(ny-1) diagonals
struct GridCounts {
  int structural, shear_both, shear_one, bend, triangles, hinges;
};
GridCounts grid_counts(int nx, int ny) {
  return {2 * nx * ny - nx - ny,
          2 * (nx - 1) * (ny - 1),
          (nx - 1) * (ny - 1),
          (nx - 2) * ny + nx * (ny - 2),
          2 * (nx - 1) * (ny - 1),
          (nx - 1) * (ny - 2) + (nx - 2) * (ny - 1) + (nx - 1) * (ny - 1)};
}

TEST(BuildersCloth, DefaultEdgeCountsMatchTheGridFormulas) {
  const int nx = 7, ny = 5;
  SceneDesc s;
  ClothGridDesc d;
  d.nx = nx;
  d.ny = ny;
  const ClothGrid g = add_cloth_grid(s, d);
  const GridCounts c = grid_counts(nx, ny);
  EXPECT_EQ(s.num_particles(), nx * ny);
  EXPECT_EQ(int(s.distances.size()), c.structural + c.shear_both + c.bend);
  EXPECT_EQ(int(g.triangles.size()), c.triangles);
  // Only what was asked for: no hinges, tethers, pins, tets, volumes.
  EXPECT_TRUE(s.dihedral_bends.empty());
  EXPECT_TRUE(s.isometric_bends.empty());
  EXPECT_TRUE(s.tethers.empty());
  EXPECT_TRUE(s.pins.empty());
  EXPECT_TRUE(s.tets.empty());
  EXPECT_TRUE(s.global_volumes.empty());
  // No pins: every particle movable, mass split equally (to round-off of a
  // sum of 35 terms).
  EXPECT_NEAR(total_mass(s), d.mass, 64 * kEps);
  for (Real m : s.masses) EXPECT_NEAR(m, d.mass / Real(nx * ny), kEps);
}

TEST(BuildersCloth, EachBendingModeEmitsOnlyItsType) {
  const int nx = 6, ny = 4;
  const GridCounts c = grid_counts(nx, ny);
  const Material m{Real(0.5), 0, 1};
  for (ClothBending b :
       {ClothBending::none, ClothBending::distance, ClothBending::dihedral, ClothBending::isometric}) {
    SceneDesc s;
    ClothGridDesc d;
    d.nx = nx;
    d.ny = ny;
    d.shear_both_diagonals = false;
    d.set_bending(b, m);
    add_cloth_grid(s, d);
    const int bend_edges = b == ClothBending::distance ? c.bend : 0;
    EXPECT_EQ(int(s.distances.size()), c.structural + c.shear_one + bend_edges);
    EXPECT_EQ(int(s.dihedral_bends.size()), b == ClothBending::dihedral ? c.hinges : 0);
    EXPECT_EQ(int(s.isometric_bends.size()), b == ClothBending::isometric ? c.hinges : 0);
    for (const auto& h : s.dihedral_bends) EXPECT_EQ(h.mat.compliance, m.compliance);
    for (const auto& h : s.isometric_bends) EXPECT_EQ(h.mat.compliance, m.compliance);
    const Model model = compile(s);  // hinges valid: non-degenerate, distinct particles
    EXPECT_EQ(model.get<DihedralBending>().size(), s.dihedral_bends.size());
  }
}

// With one diagonal per quad the distance edges are exactly the edges of the
// triangulation, and every triangle edge is one of them.
TEST(BuildersCloth, OneDiagonalShearEdgesAreTheTriangulationEdges) {
  SceneDesc s;
  ClothGridDesc d;
  d.nx = 5;
  d.ny = 6;
  d.shear_both_diagonals = false;
  d.bend_distance = false;
  const ClothGrid g = add_cloth_grid(s, d);
  std::set<std::pair<Index, Index>> dist, tri;
  for (const auto& e : s.distances) dist.insert({std::min(e.a, e.b), std::max(e.a, e.b)});
  for (const auto& t : g.triangles)
    for (int c = 0; c < 3; ++c)
      tri.insert({std::min(t[c], t[(c + 1) % 3]), std::max(t[c], t[(c + 1) % 3])});
  EXPECT_EQ(dist, tri);
  EXPECT_EQ(dist.size(), s.distances.size());  // no duplicates
}

// A flat cloth's hinges have dihedral angle 0 only if every hinge follows
// the layout (p0, p1, p2) / (p1, p0, p3) with the wings on opposite sides
// of the edge; a wrong layout reads +-pi. The triangles wind
// counter-clockwise about u x v.
TEST(BuildersCloth, HingeLayoutGivesZeroAngleOnTheFlatCloth) {
  SceneDesc s;
  ClothGridDesc d;
  d.nx = 5;
  d.ny = 4;
  d.size_u = Real(0.8);
  d.size_v = Real(0.3);  // non-square cells
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  d.set_bending(ClothBending::dihedral, Material{});
  const ClothGrid g = add_cloth_grid(s, d);
  const Model m = compile(s);
  for (const DihedralBending& h : m.get<DihedralBending>()) {
    EXPECT_NEAR(h.rest_angle, 0, 16 * kEps);
    // p2 and p3 on opposite sides of the hinge edge, in the cloth's plane.
    const Vec3 e = s.positions[h.p[1]] - s.positions[h.p[0]];
    const Real s2 = e.cross(s.positions[h.p[2]] - s.positions[h.p[0]]).dot(d.u.cross(d.v));
    const Real s3 = e.cross(s.positions[h.p[3]] - s.positions[h.p[0]]).dot(d.u.cross(d.v));
    EXPECT_GT(s2, 0);
    EXPECT_LT(s3, 0);
  }
  for (const Triangle& t : g.triangles) {
    const Vec3 n = (s.positions[t[1]] - s.positions[t[0]]).cross(s.positions[t[2]] - s.positions[t[0]]);
    EXPECT_GT(n.dot(d.u.cross(d.v)), 0);
  }
}

TEST(BuildersCloth, PinPresetsAndListAreMergedAndMassIsOverMovableParticles) {
  struct Case {
    ClothPins preset;
    std::vector<std::pair<int, int>> list;
    std::set<std::pair<int, int>> expect;
  };
  const int nx = 4, ny = 3;
  const std::vector<Case> cases = {
      {ClothPins::top_corners, {}, {{0, 0}, {3, 0}}},
      {ClothPins::top_edge, {{1, 0}}, {{0, 0}, {1, 0}, {2, 0}, {3, 0}}},  // duplicate counts once
      {ClothPins::all_corners, {{1, 1}}, {{0, 0}, {3, 0}, {0, 2}, {3, 2}, {1, 1}}},
      {ClothPins::none, {{2, 1}}, {{2, 1}}},
  };
  for (const Case& c : cases) {
    SceneDesc s;
    ClothGridDesc d;
    d.nx = nx;
    d.ny = ny;
    d.mass = Real(2.5);
    d.pins = c.preset;
    d.pinned = c.list;
    const ClothGrid g = add_cloth_grid(s, d);
    EXPECT_EQ(s.pins.size(), c.expect.size());
    EXPECT_EQ(g.pinned.size(), c.expect.size());
    const Real m = d.mass / Real(nx * ny - int(c.expect.size()));
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const bool pinned = c.expect.count({i, j}) > 0;
        EXPECT_EQ(s.masses[g.at(i, j)], pinned ? Real(0) : m) << i << "," << j;
      }
    EXPECT_NEAR(total_mass(s), d.mass, 64 * kEps);
  }
}

// Shortest path on the triangulated grid from index offset (0, 0) to
// (a, b): the diagonal (i,j)-(i+1,j+1) moves by (+1, +1) or (-1, -1) at cost
// c = sqrt(du^2 + dv^2) < du + dv. If a and b have the same sign, the best
// path takes min(|a|, |b|) diagonals and the remaining axis steps (each
// diagonal replaces one u and one v step and is shorter; no path can use
// fewer than max(|a|, |b|) steps of which at most min(|a|,|b|) diagonal).
// With opposite signs a diagonal moves away from the target in one axis, so
// the axis steps alone (Manhattan distance) are shortest.
Real grid_geodesic(int a, int b, Real du, Real dv) {
  const int ua = std::abs(a), ub = std::abs(b);
  if ((a >= 0) == (b >= 0) || a == 0 || b == 0) {
    const int m = std::min(ua, ub);
    return Real(m) * std::sqrt(du * du + dv * dv) + Real(ua - m) * du + Real(ub - m) * dv;
  }
  return Real(ua) * du + Real(ub) * dv;
}

TEST(BuildersCloth, GeodesicTetherLengthsMatchTheGridGraphClosedForm) {
  const int nx = 6, ny = 4;
  SceneDesc s;
  s.add_particle(Vec3(5, 5, 5), 1);  // an unrelated particle first: index offsets
  ClothGridDesc d;
  d.nx = nx;
  d.ny = ny;
  d.size_u = Real(1.0);  // du = 0.2 m
  d.size_v = Real(0.9);  // dv = 0.3 m
  d.pins = ClothPins::top_corners;
  d.tethers = TetherAnchors::all_pinned;
  d.tether_metric = TetherMetric::geodesic;
  const ClothGrid g = add_cloth_grid(s, d);
  const Real du = Real(0.2), dv = Real(0.3);
  ASSERT_EQ(int(s.tethers.size()), 2 * (nx * ny - 2));
  int checked = 0;
  for (const TetherDesc& t : s.tethers) {
    const int i = (t.particle - g.first) % nx, j = (t.particle - g.first) / nx;
    const int ai = (t.anchor - g.first) % nx, aj = (t.anchor - g.first) / nx;
    ASSERT_TRUE(t.length.has_value());
    // Summed edge lengths: round-off of ~10 additions of values <= 0.4 m.
    EXPECT_NEAR(*t.length, grid_geodesic(i - ai, j - aj, du, dv), 32 * kEps) << i << "," << j;
    // Never shorter than the straight line.
    EXPECT_GE(*t.length, (s.positions[t.particle] - s.positions[t.anchor]).norm() - 16 * kEps);
    ++checked;
  }
  EXPECT_EQ(checked, 2 * (nx * ny - 2));
  // Both branches of the closed form occur: anchor (0,0) to (2,1) uses one
  // diagonal; anchor (5,0) to (2,1) uses none.
  EXPECT_NEAR(grid_geodesic(2, 1, du, dv), std::sqrt(du * du + dv * dv) + du, 4 * kEps);
  EXPECT_NEAR(grid_geodesic(-3, 1, du, dv), 3 * du + dv, 4 * kEps);
}

TEST(BuildersCloth, NearestTetherPicksTheClosestAnchorByTheChosenMetric) {
  const int nx = 5, ny = 5;
  for (TetherMetric metric : {TetherMetric::euclidean, TetherMetric::geodesic}) {
    SceneDesc s;
    ClothGridDesc d;
    d.nx = nx;
    d.ny = ny;
    d.size_u = d.size_v = 1;  // du = dv = 0.25 m
    d.pins = ClothPins::top_corners;
    d.tethers = TetherAnchors::nearest_pinned;
    d.tether_metric = metric;
    d.tether_mat = Material{Real(1e-4), 0, 1};
    const ClothGrid g = add_cloth_grid(s, d);
    ASSERT_EQ(int(s.tethers.size()), nx * ny - 2);
    const Real h = Real(0.25);
    for (const TetherDesc& t : s.tethers) {
      const int i = (t.particle - g.first) % nx, j = (t.particle - g.first) / nx;
      Real l0, l1;  // to anchor (0,0) and (4,0)
      if (metric == TetherMetric::geodesic) {
        l0 = grid_geodesic(i, j, h, h);
        l1 = grid_geodesic(i - (nx - 1), j, h, h);
      } else {
        l0 = h * std::hypot(Real(i), Real(j));
        l1 = h * std::hypot(Real(i - (nx - 1)), Real(j));
      }
      // Ties go to the lower index (anchor (0,0)).
      const Index expect = l0 <= l1 + 16 * kEps ? g.at(0, 0) : g.at(nx - 1, 0);
      EXPECT_EQ(t.anchor, expect) << i << "," << j;
      EXPECT_NEAR(*t.length, std::min(l0, l1), 32 * kEps);
      EXPECT_EQ(t.mat.compliance, d.tether_mat.compliance);
    }
  }
}

TEST(BuildersCloth, BadInputNamesFieldAndValue) {
  SceneDesc s;
  ClothGridDesc d;
  d.nx = 1;
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_cloth_grid(s, d); }, {"cloth.nx", "1 x 32"}));
  d = ClothGridDesc{};
  d.pinned = {{3, 40}};
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_cloth_grid(s, d); }, {"cloth.pinned", "(3, 40)"}));
  d = ClothGridDesc{};
  d.size_v = -2;
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_cloth_grid(s, d); }, {"cloth.size_v", "-2"}));
  d = ClothGridDesc{};
  d.tethers = TetherAnchors::nearest_pinned;
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_cloth_grid(s, d); }, {"cloth.tethers", "pinned"}));
}

// Geodesic nearest_pinned tethers come from one search from all pins at
// once. Reference: a search from each pin alone (edge_path_distances) over
// the cloth's triangle edges, collected here from its triangles. Every
// tether's length is the smallest of those, exactly (the same sums), and
// its anchor is a pin at that distance. A cloth with unequal spacings in u
// and v and pins scattered inside it, so the paths are not symmetric.
TEST(BuildersCloth, GeodesicNearestPinnedTethersAreTheShortestPathFromAnyPin) {
  SceneDesc s;
  s.add_particle(Vec3(5, 5, 5), 1);  // the cloth does not start at index 0
  ClothGridDesc d;
  d.nx = 13;
  d.ny = 9;
  d.size_u = Real(1.3);
  d.size_v = Real(0.7);
  d.pins = ClothPins::none;
  d.pinned = {{0, 0}, {12, 8}, {5, 4}, {9, 1}, {2, 7}};
  d.tethers = TetherAnchors::nearest_pinned;
  d.tether_metric = TetherMetric::geodesic;
  const ClothGrid g = add_cloth_grid(s, d);
  std::set<std::array<Index, 2>> unique;
  for (const Triangle& t : g.triangles)
    for (int k = 0; k < 3; ++k) {
      const Index a = t[std::size_t(k)], b = t[std::size_t((k + 1) % 3)];
      unique.insert({std::min(a, b), std::max(a, b)});
    }
  const std::vector<std::array<Index, 2>> edges(unique.begin(), unique.end());
  std::vector<std::vector<Real>> from;
  for (const Index p : g.pinned) from.push_back(edge_path_distances(s.positions, edges, p));
  ASSERT_EQ(int(s.tethers.size()), d.nx * d.ny - int(g.pinned.size()));
  for (const TetherDesc& t : s.tethers) {
    Real best = std::numeric_limits<Real>::infinity();
    for (const auto& f : from) best = std::min(best, f[std::size_t(t.particle)]);
    ASSERT_TRUE(t.length.has_value());
    EXPECT_EQ(*t.length, best) << "particle " << t.particle;
    const auto a = std::find(g.pinned.begin(), g.pinned.end(), t.anchor);
    ASSERT_NE(a, g.pinned.end()) << "particle " << t.particle;
    EXPECT_EQ(from[std::size_t(a - g.pinned.begin())][std::size_t(t.particle)], best) << "particle " << t.particle;
  }
}

// ---------------------------------------------------------------------------
// Helpers

TEST(BuildersHelpers, EdgePathDistancesOnAChainAndUnreachable) {
  std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 2, 0), Vec3(7, 7, 7)};
  const std::vector<std::array<Index, 2>> e = {{0, 1}, {1, 2}, {0, 2}};
  const std::vector<Real> d = edge_path_distances(x, e, 0);
  EXPECT_EQ(d[0], 0);
  EXPECT_NEAR(d[1], 1, kEps);
  EXPECT_NEAR(d[2], std::sqrt(Real(5)), 4 * kEps);  // direct edge beats 1 + 2
  EXPECT_TRUE(std::isinf(d[3]));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
