#pragma once
// State: what a scene *does*. One per simulated instance; mutable.
#include <array>
#include <vector>

#include "xpbd/constraint_types.hpp"
#include "xpbd/types.hpp"

namespace xpbd {

struct Model;

struct State {
  std::vector<Vec3> x;       // m, positions
  std::vector<Vec3> x_prev;  // m, positions at the start of the last substep
  std::vector<Vec3> v;       // m/s, velocities

  // Optional external force per particle (N), constant over a step. Empty =
  // none (and no cost). If non-empty it must have one entry per particle.
  std::vector<Vec3> f_ext;

  // Pin targets (m), one per Pin element. Set pin_target to where the pin
  // must be at the end of the next step; step() moves the target linearly
  // from its previous value over the substeps.
  std::vector<Vec3> pin_target;
  std::vector<Vec3> pin_target_prev;  // value at the start of the step (internal)
  std::vector<Vec3> pin_target_now;   // value in the current substep (internal)

  // Lagrange multipliers of the last substep, one array per constraint type,
  // parallel to Model's constraint arrays. lambda is in units of [C]*kg
  // (kg*m for length constraints); the generalized force is lambda/h^2.
  std::array<std::vector<Real>, kNumConstraintTypes> lambda;

  Real time = 0;          // s, simulated time
  Real last_substep = 0;  // s, h of the last substep (for force estimates)

  template <class T>
  std::vector<Real>& lambdas() {
    return lambda[type_index_v<T>];
  }
  template <class T>
  const std::vector<Real>& lambdas() const {
    return lambda[type_index_v<T>];
  }
};

// Creates a state at the model's initial positions and velocities.
State make_state(const Model& model);

}  // namespace xpbd
