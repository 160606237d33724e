#pragma once
// SceneDesc: the editable description of a particle system. compile() checks
// it and turns it into an immutable Model (model.hpp).
#include <array>
#include <optional>
#include <vector>

#include "xpbd/constraints.hpp"
#include "xpbd/types.hpp"

namespace xpbd {

struct DistanceDesc {
  Index a = 0, b = 0;
  std::optional<Real> rest;  // m, > 0; empty = distance in the initial positions
  Material mat;
};

// Explicit particle-particle collision pair; the contact distance is the sum
// of the two particle radii, which must be > 0.
struct CollisionDesc {
  Index a = 0, b = 0;
  Material mat;
};

// Pins particle `particle` to `target` (m). A particle of mass 0 is kinematic
// and follows the target exactly; otherwise the pin is a constraint with the
// given compliance. Move the target at run time through State::pin_target.
struct PinDesc {
  Index particle = 0;
  std::optional<Vec3> target;  // empty = the particle's initial position
  Material mat;
};

// A static plane every movable particle collides with (with its radius).
struct PlaneDesc {
  Vec3 normal = Vec3::UnitY();  // need not be unit length, must be non-zero
  Real offset = 0;              // m, plane is { x : n.x/|n| = offset }
  Material mat;
};

// Point-triangle penetration: point p[0] stays on the side of the plane of
// triangle (p[1], p[2], p[3]) it is on at the start of each step, at least
// `thickness` away from it (see Penetration in constraints_contact.hpp).
// The initial triangle must not be degenerate.
struct PenetrationDesc {
  std::array<Index, 4> p{};        // point, then the triangle's three particles
  std::optional<Real> thickness;   // m, >= 0; empty = the point's radius
  Material mat;                    // compliance in m/N
};

// Dihedral bending of the hinge made of triangles (p0, p1, p2) and
// (p1, p0, p3), sharing edge (p0, p1) (see DihedralBending).
struct DihedralBendingDesc {
  std::array<Index, 4> p{};         // hinge edge p0-p1, wings p2 and p3
  std::optional<Real> rest_angle;   // rad, in [-pi, pi]; empty = initial angle
  Material mat;                     // compliance in rad^2/J (= rad/(N*m))
};

// Isometric (Bergou et al. 2006) bending of the same hinge layout. The
// cotangent weights come from the initial positions, which should be flat
// or nearly so (the constraint always pulls towards flat), and must not be
// degenerate.
struct IsometricBendingDesc {
  std::array<Index, 4> p{};  // hinge edge p0-p1, wings p2 and p3
  Material mat;              // compliance in 1/J (1/alpha = bending stiffness, J)
};

// Tetrahedron volume: signed volume (1/6)(x1-x0).((x2-x0)x(x3-x0)) is kept at
// rest_volume.
struct TetVolumeDesc {
  std::array<Index, 4> p{};
  std::optional<Real> rest_volume;  // m^3, signed, != 0; empty = initial volume (must be != 0)
  Material mat;                     // compliance in m^6/J; alpha = V0/K for bulk modulus K (Pa)
};

// Long-range attachment: particle stays within `length` of anchor.
struct TetherDesc {
  Index particle = 0, anchor = 0;
  std::optional<Real> length;  // m, > 0; empty = initial Euclidean distance
  Material mat;                // compliance in m/N
};

// Global volume of a closed surface (a balloon): the volume enclosed by the
// triangles is kept at pressure * V0, V0 = volume in the initial positions.
// The surface must be closed and consistently oriented with outward normals
// (counter-clockwise seen from outside): every directed edge (a, b) appears
// exactly once and so does (b, a).
struct GlobalVolumeDesc {
  std::vector<std::array<Index, 3>> triangles;
  Real pressure = 1;  // dimensionless, > 0: target volume / initial volume
  Material mat;       // compliance in m^6/J
};

// Opt-in particle-particle collision between all particles, between bodies
// and within one (self-collision), found by a spatial hash once per step
// (see spatial_hash.hpp for the design). Off by default: then nothing is
// built, stored or run.
struct SelfCollisionDesc {
  bool enabled = false;
  Real distance = 0;           // m, > 0 and finite: contact distance between particle centres
  // Pairs that share a Distance, bending, TetVolume or GlobalVolume-triangle
  // element never collide (explicit SceneDesc::collisions pairs never do).
  bool skip_connected = true;
  Material mat;                // compliance m/N, damping N*s/m
};

struct SceneDesc {
  // Particles, as parallel arrays.
  std::vector<Vec3> positions;   // m
  std::vector<Real> masses;      // kg, >= 0 and finite; 0 = kinematic (infinite mass)
  std::vector<Vec3> velocities;  // m/s; empty = all zero
  std::vector<Real> radii;       // m, >= 0; empty = all zero

  std::vector<DistanceDesc> distances;
  std::vector<CollisionDesc> collisions;
  std::vector<PinDesc> pins;
  std::vector<PlaneDesc> planes;
  std::vector<PenetrationDesc> penetrations;
  std::vector<DihedralBendingDesc> dihedral_bends;
  std::vector<IsometricBendingDesc> isometric_bends;
  std::vector<TetVolumeDesc> tets;
  std::vector<TetherDesc> tethers;
  std::vector<GlobalVolumeDesc> global_volumes;
  SelfCollisionDesc self_collision;  // off by default
  // Surface triangles that rigid features (box corners and edges, hull
  // vertices) collide with in the Bullet bridge (particle indices, any
  // winding). Empty = no triangle collision and no cost.
  std::vector<std::array<Index, 3>> collision_triangles;
  // The visible surface (particle indices, any winding): what a renderer
  // draws and what ray queries hit (xpbd/raycast.hpp). The builders fill it
  // (a cloth grid's triangulation, a tet box's boundary faces, a triangle
  // mesh's triangles); a rope has none. Never read by the solver.
  std::vector<std::array<Index, 3>> surface_triangles;

  // Appends a particle and returns its index. Fills velocities/radii only if
  // the caller asks for non-default values or they are already in use.
  Index add_particle(const Vec3& x, Real mass, Real radius = 0, const Vec3& v = Vec3::Zero());
  Index num_particles() const { return static_cast<Index>(positions.size()); }
};

}  // namespace xpbd
