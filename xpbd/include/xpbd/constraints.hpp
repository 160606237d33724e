#pragma once
// Constraint element types and their value/gradient functions.
//
// Every constraint type is a plain struct stored in one flat array per type
// (see model.hpp). Each type provides
//
//   static constexpr int kArity;        // number of particles
//   static constexpr bool kInequality;  // C >= 0 instead of C == 0
//   std::array<Index, kArity> p;        // particle indices
//   Material mat;                       // compliance, damping, PBD stiffness
//   static bool eval(const T&, Index k, const EvalContext&, Real& C, Vec3* grad);
//
// eval() returns false when the gradient is undefined (coincident points,
// degenerate geometry); the solver then skips that element for this
// projection. It never divides by a vanishing norm, so it never produces NaN.
// The math lives here; the bookkeeping (lambda, masses, damping) lives in the
// single generic projection in solve.hpp.
//
// The types beyond the four below live in constraints_bending.hpp
// (DihedralBending, IsometricBending), constraints_contact.hpp (Penetration,
// Tether) and constraints_volume.hpp (TetVolume, GlobalVolume). GlobalVolume
// is the one exception to the convention above: variable arity, no eval(),
// its own kernel (special_constraints.hpp).
#include <array>

#include "xpbd/types.hpp"

namespace xpbd {

// Per-constraint solver parameters.
struct Material {
  // XPBD compliance alpha = 1/stiffness. The constraint energy is
  // C^2/(2 alpha), so alpha is in [C]^2/J: m/N for length constraints,
  // rad^2/J for angles, m^6/J for volumes (each type documents its unit).
  // 0 = infinitely stiff.
  Real compliance = 0;
  // XPBD constraint damping beta (Macklin et al. 2016, eq. 26), in
  // J*s/[C]^2 (N*s/m for length constraints). The solver uses
  // gamma = alpha*beta/h, so damping has no effect on a constraint with zero
  // compliance.
  Real damping = 0;
  // PBD stiffness k in [0, 1] (dimensionless). Used by Method::pbd only; its
  // effect depends on the iteration count, which is the flaw PBD mode exists
  // to show.
  Real stiffness = 1;
};

// A static plane { x : n.x = offset }, n of unit length.
struct Plane {
  Vec3 normal = Vec3::UnitY();  // unit normal, pointing to the free side
  Real offset = 0;              // m, signed distance of the plane from the origin
};

// Everything eval() may read besides the constraint element itself.
struct EvalContext {
  const Vec3* x = nullptr;           // current particle positions
  const Vec3* pin_target = nullptr;  // per-pin target for the current substep
  const Plane* planes = nullptr;     // model planes
  // Side (+1 or -1) of each Penetration element's point relative to its
  // triangle at the start of the step (State::penetration_side). Must be set
  // whenever the model has Penetration elements.
  const Real* penetration_side = nullptr;
};

namespace detail {
// Unit direction a->b style helper shared by distance-like constraints.
// Returns false if |d| <= kDegenerateRel * scale.
inline bool normalized(const Vec3& d, Real scale, Real& len, Vec3& n) {
  len = d.norm();
  if (!(len > kDegenerateRel * scale)) return false;
  n = d / len;
  return true;
}
}  // namespace detail

// Distance (equality): C = |x_a - x_b| - rest.
// Coincident particles: direction undefined -> skipped (documented).
struct Distance {
  static constexpr int kArity = 2;
  static constexpr bool kInequality = false;
  std::array<Index, 2> p{};
  Real rest = 0;  // m, > 0
  Material mat;

  static bool eval(const Distance& c, Index, const EvalContext& ctx, Real& C, Vec3* g) {
    Real len;
    Vec3 n;
    if (!detail::normalized(ctx.x[c.p[0]] - ctx.x[c.p[1]], c.rest, len, n)) return false;
    C = len - c.rest;
    g[0] = n;
    g[1] = -n;
    return true;
  }
};

// Particle-particle collision (inequality): C = |x_a - x_b| - (r_a + r_b) >= 0.
// Same function as Distance; only active while the particles overlap.
struct Collision {
  static constexpr int kArity = 2;
  static constexpr bool kInequality = true;
  std::array<Index, 2> p{};
  Real rest = 0;  // m, sum of the two radii (> 0)
  Material mat;

  static bool eval(const Collision& c, Index, const EvalContext& ctx, Real& C, Vec3* g) {
    Real len;
    Vec3 n;
    if (!detail::normalized(ctx.x[c.p[0]] - ctx.x[c.p[1]], c.rest, len, n)) return false;
    C = len - c.rest;
    g[0] = n;
    g[1] = -n;
    return true;
  }
};

// Wall / plane (inequality): C = n.x - offset - radius >= 0 against a static
// plane of the model. One element per (plane, movable particle).
struct Wall {
  static constexpr int kArity = 1;
  static constexpr bool kInequality = true;
  std::array<Index, 1> p{};
  Index plane = 0;   // index into Model::planes
  Real radius = 0;   // m, particle thickness
  Material mat;

  static bool eval(const Wall& c, Index, const EvalContext& ctx, Real& C, Vec3* g) {
    const Plane& pl = ctx.planes[c.plane];
    C = pl.normal.dot(ctx.x[c.p[0]]) - pl.offset - c.radius;
    g[0] = pl.normal;
    return true;
  }
};

// Fixed / pin (equality): C = |x - target| with a target that may move over
// time (State::pin_target, interpolated linearly over the substeps). A pin on
// a particle with inverse mass 0 is kinematic: predict() places the particle
// on the target and this constraint has nothing to do. When the particle sits
// exactly on the target the direction is undefined and C = 0: skipped.
struct Pin {
  static constexpr int kArity = 1;
  static constexpr bool kInequality = false;
  std::array<Index, 1> p{};
  Material mat;

  static bool eval(const Pin& c, Index k, const EvalContext& ctx, Real& C, Vec3* g) {
    const Vec3 d = ctx.x[c.p[0]] - ctx.pin_target[k];
    const Real len = d.norm();
    if (!(len > Real(0))) return false;
    C = len;
    g[0] = d / len;
    return true;
  }
};

}  // namespace xpbd

// The remaining constraint types (bending, volume, penetration, tether).
#include "xpbd/constraints_bending.hpp"
#include "xpbd/constraints_contact.hpp"
#include "xpbd/constraints_volume.hpp"
