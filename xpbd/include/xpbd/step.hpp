#pragma once
#include "xpbd/model.hpp"
#include "xpbd/profile.hpp"
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
  // Symmetric Gauss-Seidel: every other sweep (counted across substeps)
  // visits the elements of each constraint type last to first. Off by
  // default. A fixed order lets the elements solved first win every sweep;
  // where the solve does not converge, that pushes the solution towards one
  // side of the mesh (a heavy ball on a grid cloth walks towards the rows
  // solved first). Alternating removes that bias but converges more slowly
  // on chains and hanging cloth pinned at the end solved first (measured:
  // Fig. 5's XPBD strain at 5 iterations rose from below 1% to 4%).
  bool alternate_sweeps = false;
  // Opt-in per-stage wall-clock breakdown (profile.hpp): when set, step()
  // adds each stage's time to *times. nullptr (default) = no timing. Does not
  // change the result: the trajectory is the same bit for bit.
  StageTimes* times = nullptr;
};

// Advances `state` by cfg.dt:
//   for each substep: predict, solve (iterations x constraint types), update velocities.
// Throws ConfigError for an invalid cfg, or if state does not match model.
// Performs no allocation.
void step(const Model& model, State& state, const StepConfig& cfg);

// Checks that cfg is valid; throws ConfigError naming the field and value.
void validate(const StepConfig& cfg);

}  // namespace xpbd
