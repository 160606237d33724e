#pragma once
// The catenary of issue 6: an elastic chain hanging between two supports,
// with the exact static equilibrium of the DISCRETE chain as its reference
// (a 20-link chain does not follow the continuous catenary curve exactly).
//
// The chain: n particles of `mass` (kg), n-1 links of rest length `spacing`
// (m) and compliance `compliance` (m/N), particle 0 pinned at a and particle
// n-1 at b, gravity g (m/s^2) along -y.
//
// The equilibrium (catenary.cpp derives it): in the vertical plane through
// a and b, every link carries the same horizontal tension H (no horizontal
// loads), and the downward-pointing vertical tension of link k (from
// particle k to k+1, k = 0 .. n-2) is V_k = V_0 - k m g (each interior
// particle hangs its weight m g on the links; the pinned end particles' own
// weight goes straight into their supports). Link k has tension
// T_k = sqrt(H^2 + V_k^2), length spacing + compliance T_k and runs from
// particle k to k+1 along (H e - V_k y) / T_k, e the horizontal unit vector
// from a towards b. Newton's method finds the (H, V_0) for which the chain
// ends at b.
#include <vector>

#include "demos/scene_spec.hpp"
#include "xpbd/types.hpp"

namespace xpbd_compare {

using xpbd::Real;
using xpbd::Vec3;

struct CatenaryParams {
  // 21 particles, 20 links of 5 cm: the chain is 1 m long at rest.
  int n = 21;
  Real mass = Real(0.1);       // kg per particle (the chain weighs 19 x 1 N between the supports)
  Real spacing = Real(0.05);   // m, rest length of a link
  Real g = 10;                 // m/s^2, along -y
  // m/N. The end links carry 11.64 N, so they stretch by 1.16e-4 m (0.23 %)
  // and the elastic chain sags 1.33 mm more than an inextensible one (RMS
  // position difference 0.88 mm, sag 0.2671 m against 0.2658 m): far
  // more than float round-off of the positions (~3e-8 m at |x| ~ 0.4 m),
  // small enough to stay a chain. alpha m = 1e-6 kg m/N as for the vertical
  // chain (compare.hpp: 1 kg, 1e-6 m/N), so at the same substep h both have
  // the same ratio alpha/(h^2 w) of compliance to inverse mass, which sets
  // how much a Gauss-Seidel sweep converges the links' stretch.
  Real compliance = Real(1e-5);
  // m, the supports: 0.8 m apart at the same height, centred on the origin
  // (small |x| keeps float round-off small). 0.8 m for a 1 m chain gives a
  // clearly visible sag of ~0.26 m.
  Vec3 a = Vec3(Real(-0.4), Real(0), Real(0));
  Vec3 b = Vec3(Real(0.4), Real(0), Real(0));
  // 1/s: velocity damping so that the run settles to the static state (the
  // equilibrium does not depend on it). 10/s damps a swing's amplitude as
  // exp(-5 t) (measured with start_angle = 0.5: RMS 0.09 m at the start,
  // 7e-5 m at 1.5 s).
  Real drag = 10;
  // rad: the scene starts at the inextensible (compliance 0) equilibrium
  // turned by this angle about the line through a and b (a rigid rotation:
  // every link at its rest length, the ends on a and b). 0 = start hanging
  // in the vertical plane, only the links' stretch is missing.
  Real start_angle = 0;
};

// Throws std::invalid_argument naming the field and value if p describes no
// chain with an equilibrium: n < 3; mass, spacing or g not > 0; compliance
// < 0; drag < 0; a non-finite value; a and b at the same horizontal position
// (a vertical chain, see chain_equilibrium); |b - a| >= (n-1) spacing (the
// chain cannot reach without stretching).
void check_catenary_params(const CatenaryParams& p);

struct CatenaryEquilibrium {
  std::vector<Vec3> x;  // m, particle positions, x[0] = a, x[n-1] = b up to `residual`
  double H = 0;         // N, horizontal tension (the same in every link)
  double V0 = 0;        // N, downward vertical tension of link 0 (at a); link k: V0 - k m g
  // N, force each support exerts on the chain, EXCLUDING the end particle's
  // own weight (which the support also carries): the tension of the end link,
  // |(H, V0)| at a and |(H, V_{n-2})| at b.
  double support_force_a = 0, support_force_b = 0;
  // N, upward components of the same: V0 at a, -V_{n-2} at b. They add up to
  // the interior particles' weight (n-2) m g.
  double support_vertical_a = 0, support_vertical_b = 0;
  int newton_iterations = 0;
  double residual = 0;  // m, |end of the chain - b| in the Newton solution (double)
};

// The static equilibrium of the elastic discrete chain, solved in double to
// round-off (residual below 1e-12 of the chain length) and rounded to Real
// at the end. Throws std::invalid_argument for invalid p
// (check_catenary_params) and std::runtime_error (with the residual) if
// Newton's method does not converge.
CatenaryEquilibrium catenary_equilibrium(const CatenaryParams& p);

// The chain as a scene: explicit particles (the end ones of mass 0, pinned
// where they start, as btSoftBody requires), n-1 distance constraints of
// rest length `spacing`, gravity, drag; starting at rest in the inextensible
// equilibrium turned by p.start_angle about the support line. frames >= 1.
// Throws std::invalid_argument for invalid p or frames.
xpbd_demos::SceneSpec catenary_scene(const CatenaryParams& p, int frames);

}  // namespace xpbd_compare
