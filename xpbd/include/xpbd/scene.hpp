#pragma once
// SceneDesc: the editable description of a particle system. compile() checks
// it and turns it into an immutable Model (model.hpp).
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

  // Appends a particle and returns its index. Fills velocities/radii only if
  // the caller asks for non-default values or they are already in use.
  Index add_particle(const Vec3& x, Real mass, Real radius = 0, const Vec3& v = Vec3::Zero());
  Index num_particles() const { return static_cast<Index>(positions.size()); }
};

}  // namespace xpbd
