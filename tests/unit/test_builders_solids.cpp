// Scene builders (xpbd/builders.hpp), the solids: the tetrahedral box
// (element counts against closed-form formulas, positive volumes, a closed
// outward surface, volume-lumped masses) and triangle meshes (counts,
// volume, dihedral angles, area-lumped masses), with their error messages.
// Every expected value is computed here from the geometry, never from the
// builder. The cloth and rope builders are in test_builders.cpp.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;
using test::throws_naming;
using test::total_mass;

// ---------------------------------------------------------------------------
// Tetrahedral box

struct BoxCounts {
  int particles, tets, edges, surface;
};
// Axis edges nx(ny+1)(nz+1) + (nx+1)ny(nz+1) + (nx+1)(ny+1)nz; each cell
// face carries one diagonal, faces (nx+1)ny nz + nx(ny+1)nz + nx ny(nz+1);
// the six-split adds one body diagonal per cell. The boundary has
// 2(nx ny + ny nz + nz nx) squares of two triangles each.
BoxCounts box_counts(int nx, int ny, int nz, TetSplit split) {
  const int axis = nx * (ny + 1) * (nz + 1) + (nx + 1) * ny * (nz + 1) + (nx + 1) * (ny + 1) * nz;
  const int faces = (nx + 1) * ny * nz + nx * (ny + 1) * nz + nx * ny * (nz + 1);
  const int cells = nx * ny * nz;
  const bool six = split == TetSplit::six;
  return {(nx + 1) * (ny + 1) * (nz + 1), (six ? 6 : 5) * cells, axis + faces + (six ? cells : 0),
          4 * (nx * ny + ny * nz + nz * nx)};
}

Real det_volume(const SceneDesc& s, const std::array<Index, 4>& p) {
  Mat3 m;
  for (int c = 0; c < 3; ++c) m.col(c) = s.positions[p[c + 1]] - s.positions[p[0]];
  return m.determinant() / 6;
}

TEST(BuildersTetBox, CountsPositiveVolumesAndClosedOutwardSurface) {
  const int nx = 3, ny = 2, nz = 2;
  const Vec3 size(Real(0.6), Real(0.5), Real(0.4));
  const Vec3 origin(1, -2, Real(0.5));
  const Real box = size.prod();
  const Real cell = box / Real(nx * ny * nz);
  for (TetSplit split : {TetSplit::five, TetSplit::six}) {
    SceneDesc s;
    s.add_particle(Vec3::Zero(), 1);  // offset the indices
    TetBoxDesc d;
    d.nx = nx;
    d.ny = ny;
    d.nz = nz;
    d.size = size;
    d.origin = origin;
    d.split = split;
    d.mass = Real(3);
    const TetBox b = add_tet_box(s, d);
    const BoxCounts c = box_counts(nx, ny, nz, split);
    EXPECT_EQ(s.num_particles() - 1, c.particles);
    ASSERT_EQ(int(s.tets.size()), c.tets);
    EXPECT_EQ(int(s.distances.size()), c.edges);
    EXPECT_EQ(int(b.surface.size()), c.surface);
    EXPECT_NEAR(total_mass(s) - 1, d.mass, 64 * kEps);

    // Every tet positive; volumes 1/6 of a cell (and 1/3 for the central
    // tet of the five-split); sum = box volume. Tolerance: determinant of
    // coordinates ~1 m with entries ~0.2 m: a few ulps of 1 m^3.
    Real sum = 0;
    int sixths = 0, thirds = 0;
    for (const auto& t : s.tets) {
      const Real v = det_volume(s, t.p);
      EXPECT_GT(v, 0);
      sum += v;
      if (std::abs(v - cell / 6) < 64 * kEps) ++sixths;
      if (std::abs(v - cell / 3) < 64 * kEps) ++thirds;
    }
    EXPECT_NEAR(sum, box, 256 * kEps);
    EXPECT_EQ(sixths, split == TetSplit::six ? 6 * nx * ny * nz : 4 * nx * ny * nz);
    EXPECT_EQ(thirds, split == TetSplit::six ? 0 : nx * ny * nz);

    // Boundary triangles lie on the box faces with outward normals, and
    // enclose the box volume (divergence theorem). If neighbouring cells cut
    // a shared face along different diagonals, the mismatched halves would
    // show up as extra boundary triangles inside the box.
    const Vec3 centre = origin + size / 2;
    Real enclosed = 0;
    for (const Triangle& t : b.surface) {
      const Vec3 a = s.positions[t[0]], p1 = s.positions[t[1]], p2 = s.positions[t[2]];
      const Vec3 n = (p1 - a).cross(p2 - a);
      const Vec3 mid = (a + p1 + p2) / 3 - centre;
      int axis;
      n.cwiseAbs().maxCoeff(&axis);
      EXPECT_NEAR(n.norm(), std::abs(n[axis]), 64 * kEps);  // axis-aligned
      EXPECT_NEAR(std::abs(mid[axis]), size[axis] / 2, 64 * kEps);  // on the box face
      EXPECT_GT(n[axis] * mid[axis], 0);  // outward
      enclosed += a.cross(p1).dot(p2) / 6;
    }
    EXPECT_NEAR(enclosed, box, 256 * kEps);

    // compile() accepts it: rest volumes positive and non-degenerate.
    const Model m = compile(s);
    for (const TetVolume& t : m.get<TetVolume>()) EXPECT_GT(t.rest_volume, 0);
  }
}

// Volume lumping of a 2 x 2 x 2 box: the centre particle (1, 1, 1).
//  - six-split: each vertex of the Kuhn triangulation lies in 24 tets of
//    volume cell/6, so it gets 24 * cell/24 = cell: mass M/8.
//  - five-split: (1,1,1) has odd index sum, so in each of its 8 cells it is
//    a corner of the central tet (cell/3) and of 3 corner tets (cell/6):
//    8 * (cell/12 + 3 cell/24) = (5/3) cell, mass (5/3) M/8. An even
//    vertex, e.g. (1, 1, 0) on the bottom face, is in one corner tet per
//    cell: 4 cells * cell/24 = cell/6, mass M/48.
TEST(BuildersTetBox, VolumeLumpedMassesMatchTheClosedForm) {
  for (TetSplit split : {TetSplit::five, TetSplit::six}) {
    SceneDesc s;
    TetBoxDesc d;
    d.nx = d.ny = d.nz = 2;
    d.mass = Real(8);
    d.split = split;
    const TetBox b = add_tet_box(s, d);
    const Real centre = s.masses[b.at(1, 1, 1)];
    if (split == TetSplit::six) {
      EXPECT_NEAR(centre, d.mass / 8, 64 * kEps);
    } else {
      EXPECT_NEAR(centre, Real(5) / 3 * d.mass / 8, 64 * kEps);
      EXPECT_NEAR(s.masses[b.at(1, 1, 0)], d.mass / 48, 64 * kEps);
    }
  }
}

TEST(BuildersTetBox, PinsBulkModulusAndErrors) {
  SceneDesc s;
  TetBoxDesc d;
  d.nx = 2;
  d.ny = 1;
  d.nz = 1;
  d.size = Vec3(2, 1, 1);
  d.mass = 1;
  d.bulk_modulus = Real(1e5);  // Pa
  d.edges = false;
  d.pinned = {{0, 0, 0}, {0, 1, 1}};
  const TetBox b = add_tet_box(s, d);
  EXPECT_TRUE(s.distances.empty());
  EXPECT_EQ(s.pins.size(), 2u);
  EXPECT_EQ(s.masses[b.at(0, 0, 0)], 0);
  EXPECT_EQ(s.masses[b.at(0, 1, 1)], 0);
  EXPECT_NEAR(total_mass(s), d.mass, 64 * kEps);  // over the movable particles
  // Six-split of unit cells: every tet 1/6 m^3, compliance V0/K (V0 from a
  // determinant of unit vectors: exact to a few ulps).
  const Real expect = (Real(1) / 6) / d.bulk_modulus;
  for (const auto& t : s.tets) EXPECT_NEAR(t.mat.compliance, expect, 8 * kEps * expect);

  d = TetBoxDesc{};
  d.nz = 0;
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_tet_box(s, d); }, {"tet_box.nx/ny/nz", "4 x 4 x 0"}));
  d = TetBoxDesc{};
  d.size = Vec3(1, 0, 1);
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_tet_box(s, d); }, {"tet_box.size.y", "0"}));
  d = TetBoxDesc{};
  d.pinned = {{5, 0, 0}};
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_tet_box(s, d); }, {"tet_box.pinned", "(5, 0, 0)"}));
}

// ---------------------------------------------------------------------------
// Triangle mesh

// Regular tetrahedron with edge sqrt(8): vertices (1,1,1), (1,-1,-1),
// (-1,1,-1), (-1,-1,1); faces wound counter-clockwise seen from outside.
TriangleMesh regular_tet() {
  TriangleMesh m;
  m.positions = {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  return m;
}

// Unit square split along (0)-(2).
TriangleMesh open_quad() {
  TriangleMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

TEST(BuildersMesh, ClosedTetrahedronCountsVolumeAndDihedralAngles) {
  SceneDesc s;
  s.add_particle(Vec3(9, 9, 9), 1);
  TriangleMeshDesc d;
  d.kind = MeshKind::closed_surface;
  d.bending = HingeBending::dihedral;
  d.mass = Real(2);
  d.pressure = Real(1.5);
  d.scale = Real(0.5);
  d.offset = Vec3(0, 3, 0);
  const MeshResult r = add_triangle_mesh(s, regular_tet(), d);
  EXPECT_EQ(r.first, 1);
  EXPECT_EQ(s.num_particles(), 5);
  EXPECT_EQ(r.edges.size(), 6u);  // E = 3F/2 for a closed triangle mesh
  EXPECT_EQ(s.distances.size(), 6u);
  EXPECT_EQ(r.hinges, 6u);
  ASSERT_EQ(s.dihedral_bends.size(), 6u);
  ASSERT_EQ(s.global_volumes.size(), 1u);
  EXPECT_EQ(s.global_volumes[0].pressure, d.pressure);
  // Equal faces: each vertex gets a quarter of the mass.
  for (Index v = 1; v < 5; ++v) EXPECT_NEAR(s.masses[v], d.mass / 4, 16 * kEps);
  EXPECT_EQ(s.positions[1], Vec3(Real(0.5), Real(3.5), Real(0.5)));

  const Model m = compile(s);
  // Regular tetrahedron of edge a = sqrt(8) * 0.5: V = a^3 / (6 sqrt 2).
  const Real a = std::sqrt(Real(8)) * Real(0.5);
  EXPECT_NEAR(m.get<GlobalVolume>()[0].rest_volume, a * a * a / (6 * std::sqrt(Real(2))), 64 * kEps);
  // The interior dihedral angle is acos(1/3), so the normals of two faces
  // meet at pi - acos(1/3); the hinge angle has that magnitude.
  const Real expect = std::numbers::pi_v<Real> - std::acos(Real(1) / 3);
  for (const DihedralBending& h : m.get<DihedralBending>())
    EXPECT_NEAR(std::abs(h.rest_angle), expect, 64 * kEps);
}

TEST(BuildersMesh, OpenQuadAsClothHasOneHingeAndAreaLumpedMasses) {
  SceneDesc s;
  TriangleMeshDesc d;
  d.bending = HingeBending::isometric;
  d.mass = Real(6);
  const MeshResult r = add_triangle_mesh(s, open_quad(), d);
  EXPECT_EQ(r.edges.size(), 5u);
  EXPECT_EQ(r.hinges, 1u);
  EXPECT_EQ(s.isometric_bends.size(), 1u);
  EXPECT_TRUE(s.dihedral_bends.empty());
  EXPECT_TRUE(s.global_volumes.empty());
  // Each triangle has area 1/2 and gives 1/6 of the total area to each
  // corner: the diagonal's ends (0, 2) get 1/3 of the mass, the others 1/6.
  EXPECT_NEAR(s.masses[0], d.mass / 3, 16 * kEps);
  EXPECT_NEAR(s.masses[2], d.mass / 3, 16 * kEps);
  EXPECT_NEAR(s.masses[1], d.mass / 6, 16 * kEps);
  EXPECT_NEAR(s.masses[3], d.mass / 6, 16 * kEps);
  // Hinge edge (0, 2) with wings 1 and 3.
  const auto& p = s.isometric_bends[0].p;
  EXPECT_EQ(std::min(p[0], p[1]), 0);
  EXPECT_EQ(std::max(p[0], p[1]), 2);
  EXPECT_EQ(std::min(p[2], p[3]), 1);
  EXPECT_EQ(std::max(p[2], p[3]), 3);
  (void)compile(s);
}

TEST(BuildersMesh, ErrorsNameTheMeshAndTheVertices) {
  SceneDesc s;
  TriangleMeshDesc d;
  d.name = "sheet.obj";
  d.index_base = 1;
  // Closed surface requested on an open mesh: name an open edge.
  d.kind = MeshKind::closed_surface;
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_triangle_mesh(s, open_quad(), d); },
                            {"sheet.obj", "not closed", "edge (1, 2)"}));
  EXPECT_EQ(s.num_particles(), 0);  // nothing added on failure

  // Inconsistent orientation (one face flipped) on a closed mesh.
  TriangleMesh flipped = regular_tet();
  std::swap(flipped.triangles[3][1], flipped.triangles[3][2]);
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_triangle_mesh(s, flipped, d); },
                            {"sheet.obj", "not consistently oriented", "same direction"}));

  // All faces flipped: closed and consistent, but inward.
  TriangleMesh inward = regular_tet();
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_triangle_mesh(s, inward, d); }, {"sheet.obj", "volume of -"}));

  d.kind = MeshKind::cloth;
  TriangleMesh bad = open_quad();
  bad.triangles[1][2] = 7;
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_triangle_mesh(s, bad, d); },
                            {"sheet.obj", "triangle 2", "vertex 8", "1 to 4"}));
  bad = open_quad();
  bad.triangles[0] = {0, 1, 1};
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_triangle_mesh(s, bad, d); }, {"triangle 1", "repeats"}));
  bad = open_quad();
  bad.positions.push_back(Vec3(5, 5, 5));
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_triangle_mesh(s, bad, d); }, {"vertex 5", "no triangle"}));
  // Three triangles on edge (0, 2): non-manifold.
  bad = open_quad();
  bad.positions.push_back(Vec3(Real(0.5), Real(0.5), 1));
  bad.triangles.push_back({0, 2, 4});
  EXPECT_TRUE(throws_naming<SceneError>([&] { add_triangle_mesh(s, bad, d); },
                            {"sheet.obj", "edge (1, 3)", "3 triangles", "non-manifold"}));
  EXPECT_EQ(s.num_particles(), 0);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
