#pragma once
// The parts of the constraint types that do not fit the generic per-element
// projection (solve.hpp):
//  - Penetration needs the side of each point at the start of the step,
//    recorded once per step by begin_step_constraints();
//  - GlobalVolume has variable arity and its own kernel.
// step() calls begin_step_constraints() once at the start of a step and
// solve_global_volumes() at GlobalVolume's place in the solve order.
#include <cstddef>

#include "xpbd/model.hpp"
#include "xpbd/solve.hpp"
#include "xpbd/state.hpp"

namespace xpbd {

// Checks the State arrays of the types above against the model (throws
// ConfigError naming the array and sizes), then records the penetration sides.
void begin_step_constraints(const Model& m, State& s);

// s.penetration_side[k] = side of Penetration element k's point at s.x.
void record_penetration_sides(const Model& m, State& s);

// Volume (m^3) enclosed by surface g at positions x (indexed by particle).
// If grad is not null, also writes dV/dx (m^2) of g's vertex v to grad[v] for
// v in [g.vert_begin, g.vert_end) (parallel to Model::global_volume_verts);
// other entries are not touched. Positions are taken relative to the
// surface's first vertex, which leaves V and its gradient unchanged for a
// closed surface and keeps round-off proportional to the surface's size,
// not to its distance from the origin.
Real global_volume(const Model& m, const GlobalVolume& g, const Vec3* x, Vec3* grad);

// One Gauss-Seidel projection of every GlobalVolume element (XPBD or PBD, as
// project_all does for the fixed-arity types), using s.volume_grad as
// scratch. No allocation.
void solve_global_volumes(const Model& m, State& s, const SolveContext& sc);

}  // namespace xpbd
