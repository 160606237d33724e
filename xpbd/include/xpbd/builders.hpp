#pragma once
// Scene builders shared by demos, tests and benchmarks. Each appends particles
// and only the constraint types asked for to a SceneDesc: a cloth without
// bending gets no bending elements, a mesh without tethers no tethers.
//
//   add_cloth_grid     rectangular cloth: distance edges, optional hinge
//                      bending, pins and tethers
//   add_rope           chain of particles joined by distance constraints
//   add_tet_box        box of tetrahedra ("soft cube"): TetVolume + edges
//   add_triangle_mesh  an indexed triangle mesh as cloth or as a closed,
//                      pressurised surface (the OBJ loader of the xpbd_io
//                      library, xpbd/io/obj.hpp, feeds it from a file)
//
// Builders throw SceneError (xpbd/error.hpp) for bad input, naming the field
// and value. Rest lengths, angles and volumes are left to compile(), which
// takes them from the initial positions, except where the builder knows a
// value the positions do not give (geodesic tether lengths).
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "xpbd/scene.hpp"

namespace xpbd {

using Triangle = std::array<Index, 3>;

// Bending across the interior edges of a triangulation (each edge shared by
// two triangles). Layout of each element: the hinge edge (p0, p1) in the
// direction of the first triangle that has it, p2 = that triangle's third
// vertex, p3 = the other triangle's third vertex (see constraints_bending.hpp).
enum class HingeBending {
  none,
  dihedral,   // DihedralBending, compliance in rad^2/J
  isometric,  // IsometricBending, compliance in 1/J
};

// ---------------------------------------------------------------------------
// Cloth grid

// Pin presets. j = 0 is the "top" edge (the row along u through `origin`).
enum class ClothPins {
  none,
  top_corners,  // (0, 0) and (nx-1, 0)
  top_edge,     // every (i, 0)
  all_corners,  // the four corners
};

// Bending models, one at a time (ClothGridDesc::set_bending).
enum class ClothBending { none, distance, dihedral, isometric };

// Long-range attachments (Tether elements) from movable particles to the
// pinned ones.
enum class TetherAnchors {
  none,
  all_pinned,      // one tether per (movable particle, pinned particle)
  nearest_pinned,  // one tether per movable particle, to the nearest pinned
                   // particle by tether_metric (ties: lowest index; a
                   // geodesic tie made only by round-off may keep the pin
                   // that was nearer along the way)
};
enum class TetherMetric {
  euclidean,  // length = straight-line distance in the initial positions
  geodesic,   // length = shortest path along the triangulation's edges
              // (structural edges and the one diagonal per quad), by Dijkstra
};

// A rectangular cloth of nx * ny particles in the plane through `origin`
// spanned by axes u (along the i index) and v (along the j index), total size
// size_u * size_v metres. Particle (i, j) has index first + j*nx + i.
//
// Triangulation: quad (i, j) is split along the diagonal (i, j)-(i+1, j+1)
// into triangles ((i,j), (i+1,j), (i+1,j+1)) and ((i,j), (i+1,j+1), (i,j+1)),
// wound counter-clockwise about u x v. Hinge bending and geodesic tethers use
// this triangulation. Shear edges are both diagonals of every quad (the
// default, as btSoftBody's cloth), or only the triangulation's diagonal
// (shear_both_diagonals = false), in which case the distance edges are
// exactly the triangulation's edges.
//
// Edge order in SceneDesc::distances: structural edges particle by particle
// ((i,j)-(i+1,j) then (i,j)-(i,j+1)), then shear, then bending-distance.
// The mass of one particle of a cloth grid (i, j) or a rope (particle i, j
// unused), in place of the generator's even share (kg, finite and > 0).
struct ParticleMass {
  int i = 0, j = 0;
  Real mass = 0;
};

struct ClothGridDesc {
  int nx = 32, ny = 32;                 // particles per side, >= 2
  Real size_u = 1, size_v = 1;          // m, > 0
  Vec3 origin = Vec3::Zero();           // m, position of particle (0, 0)
  Vec3 u = Vec3::UnitX(), v = -Vec3::UnitY();  // in-plane axes (unit, orthogonal)
  Real mass = 1;                        // kg, total over all movable particles, split equally
  Real radius = 0;                      // m, particle thickness
  Material stretch;                     // structural edges (i,j)-(i+1,j), (i,j)-(i,j+1); m/N
  bool shear = true;                    // diagonal edges (see above)
  bool shear_both_diagonals = true;     // false: only the triangulation's diagonal
  Material shear_mat;                   // m/N
  bool bend_distance = true;            // distance edges (i,j)-(i+2,j), (i,j)-(i,j+2)
  Material bend_mat;                    // m/N
  HingeBending hinge_bending = HingeBending::none;  // over the interior triangulation edges
  Material hinge_mat;                   // rad^2/J (dihedral) or 1/J (isometric)
  // Pinned particles: the preset plus the (i, j) listed (duplicates count
  // once). Pinned particles get mass 0 (kinematic) and a Pin at their
  // initial position.
  ClothPins pins = ClothPins::none;
  std::vector<std::pair<int, int>> pinned;
  // Tethers from every movable particle to the pinned particles. Requires at
  // least one pinned particle.
  TetherAnchors tethers = TetherAnchors::none;
  TetherMetric tether_metric = TetherMetric::geodesic;
  Material tether_mat;                  // m/N
  // m/s: the initial velocity of every movable particle (a thrown cloth).
  Vec3 velocity = Vec3::Zero();
  // Masses of single movable particles (i, j) in place of their share of
  // `mass` (the total is then no longer `mass`); a pinned particle cannot
  // be listed; a particle listed twice takes the last.
  std::vector<ParticleMass> particle_masses;
  // Append the triangulation to SceneDesc::collision_triangles, so rigid
  // features (box corners and edges) collide with the cloth's faces in the
  // Bullet bridge, not only with its particles.
  bool collision_triangles = false;

  // Convenience: exactly one bending model, with material m (m/N for
  // distance, rad^2/J for dihedral, 1/J for isometric). Sets bend_distance,
  // hinge_bending and bend_mat or hinge_mat.
  ClothGridDesc& set_bending(ClothBending b, const Material& m);
};

// add_cloth_grid, add_tet_box and add_triangle_mesh also append their
// visible surface (the triangulation, the boundary faces, the mesh's
// triangles) to SceneDesc::surface_triangles.
struct ClothGrid {
  Index first = 0;  // index of particle (0, 0)
  int nx = 0, ny = 0;
  std::vector<Triangle> triangles;  // the triangulation above, particle indices
  std::vector<Index> pinned;        // pinned particles, increasing
  Index at(int i, int j) const { return first + j * nx + i; }
};

ClothGrid add_cloth_grid(SceneDesc& scene, const ClothGridDesc& d);

// ---------------------------------------------------------------------------
// Rope / chain

// A chain of n particles from `start` along `dir` (unit) with spacing
// `spacing` (m), each of mass `mass` (kg), joined by distance constraints.
// If pin_first, particle 0 has mass 0 and a kinematic pin.
struct RopeDesc {
  int n = 20;
  Vec3 start = Vec3::Zero();
  Vec3 dir = -Vec3::UnitY();
  Real spacing = Real(0.01);
  Real mass = 1;
  Real radius = 0;
  bool pin_first = true;
  Material mat;
  // m/s: the initial velocity of every movable particle.
  Vec3 velocity = Vec3::Zero();
  // Masses of single particles (ParticleMass::i in 0 .. n-1; j unused) in
  // place of `mass`: a heavy end is {n - 1, 0, 2}. The pinned first particle
  // cannot be listed; a particle listed twice takes the last.
  std::vector<ParticleMass> particle_masses;
};

// Returns the index of the first particle.
Index add_rope(SceneDesc& scene, const RopeDesc& d);

// ---------------------------------------------------------------------------
// Tetrahedral box ("soft cube")

// How each cubic cell is split into tetrahedra.
enum class TetSplit {
  // 5 tets: four corner tets (volume 1/6 of the cell each) around a central
  // one (1/3). The split is mirrored in every other cell (by the parity of
  // i + j + k) so that neighbouring cells cut their shared face along the
  // same diagonal.
  five,
  // 6 tets around the cell diagonal (0,0,0)-(1,1,1) (Kuhn / Freudenthal),
  // each of volume 1/6; the same split in every cell is conforming.
  six,
};

// An axis-aligned box of nx * ny * nz cells, (nx+1)(ny+1)(nz+1) particles.
// Particle (i, j, k) sits at origin + (i*size.x/nx, j*size.y/ny, k*size.z/nz)
// and has index first + (k*(ny+1) + j)*(nx+1) + i. Every tet is listed with
// positive signed volume (TetVolume::volume > 0).
struct TetBoxDesc {
  int nx = 4, ny = 4, nz = 4;             // cells per axis, >= 1
  Vec3 origin = Vec3::Zero();             // m, corner (0, 0, 0)
  Vec3 size = Vec3::Ones();               // m, each component > 0
  TetSplit split = TetSplit::six;
  // kg, total over the movable particles. Lumped by volume: every tet gives
  // a quarter of its volume to each of its corners; the masses are then
  // scaled so that the movable particles carry `mass` (uniform density when
  // nothing is pinned).
  Real mass = 1;
  Real radius = 0;                        // m
  // TetVolume elements. Compliance in m^6/J. If bulk_modulus > 0 (Pa) each
  // tet gets compliance V0/K instead (V0 its rest volume), which makes the
  // stiffness independent of the resolution.
  Material volume_mat;
  Real bulk_modulus = 0;
  bool edges = true;                      // Distance elements on every tet edge (once each)
  Material edge_mat;                      // m/N
  std::vector<std::array<int, 3>> pinned; // (i, j, k) of pinned particles (mass 0, kinematic)
};

struct TetBox {
  Index first = 0;
  int nx = 0, ny = 0, nz = 0;  // cells
  std::vector<std::array<Index, 4>> tets;  // particle indices, positive volume
  std::vector<Triangle> surface;           // boundary faces, counter-clockwise seen from outside
  Index at(int i, int j, int k) const { return first + (k * (ny + 1) + j) * (nx + 1) + i; }
};

TetBox add_tet_box(SceneDesc& scene, const TetBoxDesc& d);

// ---------------------------------------------------------------------------
// Triangle mesh

struct TriangleMesh {
  std::vector<Vec3> positions;      // m
  std::vector<Triangle> triangles;  // 0-based indices into positions
};

enum class MeshKind {
  // Distance edges on every mesh edge, optional hinge bending on the
  // interior edges. Open or closed; each edge in at most two triangles.
  cloth,
  // Edges, optional bending, and one GlobalVolume with `pressure`. The mesh
  // must be closed (every edge in exactly two triangles), consistently
  // oriented and wound counter-clockwise seen from outside.
  closed_surface,
};

struct TriangleMeshDesc {
  MeshKind kind = MeshKind::cloth;
  // Placement: particle position = offset + scale * mesh position.
  Real scale = 1;                 // dimensionless, > 0
  Vec3 offset = Vec3::Zero();     // m
  // kg, total over all particles, lumped by area: every triangle gives a
  // third of its area to each corner (uniform surface density).
  Real mass = 1;
  Real radius = 0;                // m
  Material edge_mat;              // m/N
  HingeBending bending = HingeBending::none;
  Material bend_mat;              // rad^2/J (dihedral) or 1/J (isometric)
  Real pressure = 1;              // closed_surface: target volume / initial volume (> 0)
  Material volume_mat;            // closed_surface: m^6/J
  // For error messages: what the mesh is called (e.g. its file path) and the
  // number given to its first vertex and first triangle (1 for OBJ files,
  // which count from 1; triangle k is then the k-th face unless polygons
  // were triangulated).
  std::string name = "mesh";
  int index_base = 0;
};

struct MeshResult {
  Index first = 0;                       // particle of mesh vertex 0 (vertex v -> first + v)
  std::vector<Triangle> triangles;       // particle indices
  std::vector<std::array<Index, 2>> edges;  // distinct edges, particle indices
  std::size_t hinges = 0;                // interior edges (bending elements if asked for)
};

// Every vertex must be used by a triangle (a free vertex would get no mass).
MeshResult add_triangle_mesh(SceneDesc& scene, const TriangleMesh& mesh, const TriangleMeshDesc& d);

// ---------------------------------------------------------------------------
// Helpers the builders use, exposed for tests and other builders.

// The hinges of a triangle list (interior edges shared by exactly two
// triangles), in the layout of HingeBending above, ordered by edge. Throws
// SceneError if an edge is shared by more than two triangles (non-manifold);
// the message starts with `name` and numbers vertices and triangles from
// `index_base`.
std::vector<std::array<Index, 4>> mesh_hinges(const std::vector<Triangle>& triangles,
                                              const std::string& name = "mesh",
                                              int index_base = 0);

// Shortest-path distances (m) from `source` to every particle along the
// given edges, weighted by their lengths in `positions` (Dijkstra). Indices
// are particle indices; unreachable particles get +infinity.
std::vector<Real> edge_path_distances(const std::vector<Vec3>& positions,
                                      const std::vector<std::array<Index, 2>>& edges, Index source);

}  // namespace xpbd
