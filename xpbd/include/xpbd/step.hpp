#pragma once
#include "xpbd/model.hpp"
#include "xpbd/state.hpp"

namespace xpbd {

enum class Method {
  xpbd,  // Algorithm 2 of the seed report: compliance alpha, lambda reset per substep
  pbd,   // Algorithm 1: stiffness k in [0, 1], iteration-dependent by design
};

struct StepConfig {
  Real dt = Real(1) / Real(60);  // s, length of one step (> 0)
  int substeps = 10;             // >= 1; substep h = dt / substeps
  int iterations = 1;            // >= 1, Gauss-Seidel sweeps per substep
  Method method = Method::xpbd;
  Vec3 gravity{Real(0), Real(-9.81), Real(0)};  // m/s^2
  // Velocity damping rate (1/s): v *= exp(-drag*h) every substep. 0 = none.
  Real drag = 0;
};

// Advances `state` by cfg.dt:
//   for each substep: predict, solve (iterations x constraint types), update velocities.
// Throws ConfigError for an invalid cfg, or if state does not match model.
// Performs no allocation.
void step(const Model& model, State& state, const StepConfig& cfg);

// Checks that cfg is valid; throws ConfigError naming the field and value.
void validate(const StepConfig& cfg);

}  // namespace xpbd
