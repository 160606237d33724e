#pragma once
// Read-only measurements of a State: energies, momentum, strain, and force
// estimates from the Lagrange multipliers.
#include "xpbd/model.hpp"
#include "xpbd/state.hpp"

namespace xpbd {

Real kinetic_energy(const Model& m, const State& s);                         // J, movable particles
Real gravity_potential(const Model& m, const State& s, const Vec3& gravity);  // J, -sum m g.x
Vec3 linear_momentum(const Model& m, const State& s);                        // kg*m/s, movable particles
Real total_mass(const Model& m);                                             // kg, movable particles

// Distance constraints: max and mean of |len/rest - 1| (dimensionless).
struct Strain {
  Real max = 0;
  Real mean = 0;
};
Strain distance_strain(const Model& m, const State& s);

// distance_strain(m, s).max without a square root or a division per
// element (len^2 against the bounds times rest^2, in double): the same
// value to within a few units in the last place, at about half the cost.
// A NaN length is skipped as there, an infinite one gives infinity. The
// bridge's divergence check runs it after every step.
Real max_distance_strain(const Model& m, const State& s);

// The largest residual of the Distance elements' XPBD equation in the last
// substep, over the rest length (dimensionless, like a strain):
//   |C + at lambda + gamma n.((x_a - x_prev_a) - (x_b - x_prev_b))| / rest,
// C = len - rest, at = alpha/h^2, gamma = alpha beta/h, h = s.last_substep,
// lambda the element's multiplier after the step (Macklin et al. 2016,
// eqs. 9 and 26). It is the part of |len/rest - 1| that the element's
// compliance (under the force lambda/h^2 of the last substep) and its
// damping do not explain: the solve's error, 0 where it has converged. At
// compliance 0 it is the strain; an element of a soft material at rest
// under load has its stretch in the strain and not here. Meaningful after
// an XPBD step (Method::pbd's multipliers are not XPBD's); before any step
// (h = 0) it is the strain. A NaN residual is skipped, an infinite one
// gives infinity (as max_distance_strain).
Real max_distance_residual(const Model& m, const State& s);

// Generalized force of constraint k of type T in the last substep:
// lambda/h^2 (N for length constraints). Sign: positive pushes C up, so a
// stretched distance constraint (C > 0) has a negative value (tension).
template <class T>
Real constraint_force(const State& s, std::size_t k) {
  const Real h = s.last_substep;
  return h > Real(0) ? s.lambdas<T>()[k] / (h * h) : Real(0);
}

// Force vector (N) constraint k of type T applies to its i-th particle:
// lambda * grad_i C / h^2, with the gradient at the current positions.
// Zero where the gradient is undefined.
template <class T>
Vec3 constraint_force_on(const Model& m, const State& s, std::size_t k, int i) {
  EvalContext ctx{s.x.data(), s.pin_target_now.data(), m.planes.data(),
                  s.penetration_side.data()};
  Real C;
  Vec3 g[T::kArity];
  if (!T::eval(m.get<T>()[k], static_cast<Index>(k), ctx, C, g)) return Vec3::Zero();
  return constraint_force<T>(s, k) * g[i];
}

}  // namespace xpbd
