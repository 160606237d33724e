#pragma once
// Opt-in per-stage wall-clock breakdown of step() (docs/stages.md).
//
// Set StepConfig::times to a StageTimes and step() adds, for every stage
// that has work in that step, the stage's std::chrono::steady_clock time (ns)
// and one call per run of the stage. A stage without work (a constraint type
// with no elements, self-collision switched off, no body contacts, ...) is
// neither timed nor counted, so its calls stay 0: a scene's breakdown shows
// no stage it does not use. With StepConfig::times == nullptr (the default)
// nothing is timed; each stage then costs one branch.
//
// StageTimes is a fixed-size array: timing allocates nothing. The timer's own
// cost (two clock reads per timed stage run, about 20-50 ns each) is included
// in the stage times; with many substeps x iterations on a tiny scene it can
// dominate, so compare breakdowns, not absolute timed vs untimed wall times.
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>

#include "xpbd/constraint_types.hpp"

namespace xpbd {

// Stage indices, in the order step() runs them.
namespace stage {
// Once per step: validation, the per-step constraint data (penetration
// sides), the host's rigid-body lists checked and sized, and the compiled
// streams' per-step factors (the coloured sweeps, and the array order over
// its levels).
inline constexpr std::size_t step_setup = 0;
// Once per step: the self-collision candidate search (spatial hash).
inline constexpr std::size_t self_collision_search = 1;
// Every substep: pin targets, particle and body prediction, multiplier reset;
// and the previous substep's particle velocity update when no contact
// needs the velocities in between (step() runs both in one pass).
inline constexpr std::size_t predict = 2;
// Every iteration: one stage per constraint type, at first_constraint +
// type_index_v<T> (ConstraintTypes order).
inline constexpr std::size_t first_constraint = 3;
// Every iteration, after the constraint types:
inline constexpr std::size_t self_collision_solve = first_constraint + kNumConstraintTypes;
inline constexpr std::size_t body_attachments = self_collision_solve + 1;
inline constexpr std::size_t body_contacts = body_attachments + 1;
inline constexpr std::size_t triangle_contacts = body_contacts + 1;
// Every substep: particle and body velocities from the position change
// (the particles' in `predict` of the next substep, but for the last
// substep, when the step has no particle or triangle contacts).
inline constexpr std::size_t velocity_update = triangle_contacts + 1;
// Every substep: dynamic friction and restitution of body contacts.
inline constexpr std::size_t contact_velocities = velocity_update + 1;
inline constexpr std::size_t count = contact_velocities + 1;

template <class T>
inline constexpr std::size_t of = first_constraint + type_index_v<T>;
}  // namespace stage

// Name of stage k < stage::count, e.g. "predict", "distance", "body_contacts"
// (constraint types by their snake_case type name: "dihedral_bending").
inline constexpr std::array<const char*, stage::count> kStageNames = {
    "step_setup", "self_collision_search", "predict",
    // ConstraintTypes, in order (the static_assert below catches a new type).
    "distance", "dihedral_bending", "isometric_bending", "tet_volume", "global_volume",
    "collision", "wall", "penetration", "tether", "pin",
    "self_collision_solve", "body_attachments", "body_contacts", "triangle_contacts",
    "velocity_update", "contact_velocities"};
static_assert(kNumConstraintTypes == 10 && stage::of<Distance> == 3 &&
                  stage::of<DihedralBending> == 4 && stage::of<IsometricBending> == 5 &&
                  stage::of<TetVolume> == 6 && stage::of<GlobalVolume> == 7 &&
                  stage::of<Collision> == 8 && stage::of<Wall> == 9 &&
                  stage::of<Penetration> == 10 && stage::of<Tether> == 11 && stage::of<Pin> == 12,
              "ConstraintTypes changed: update kStageNames");
inline const char* stage_name(std::size_t k) { return k < stage::count ? kStageNames[k] : "?"; }

struct StageTimes {
  std::array<std::int64_t, stage::count> ns{};     // ns, summed over the timed steps
  std::array<std::int64_t, stage::count> calls{};  // runs of the stage with work
  std::int64_t steps = 0;                          // step() calls timed

  void clear() { *this = StageTimes{}; }
  // Adds another breakdown (e.g. of several systems).
  StageTimes& operator+=(const StageTimes& o) {
    for (std::size_t k = 0; k < stage::count; ++k) {
      ns[k] += o.ns[k];
      calls[k] += o.calls[k];
    }
    steps += o.steps;
    return *this;
  }
};

// Runs f(); if t is set and `work` is true, adds f's wall time to stage k of
// *t and counts one call. Used by step(); hosts may use it for their own
// stages (Times: any struct with arrays `ns` and `calls`, like StageTimes).
template <class Times, class F>
inline void timed(Times* t, std::size_t k, bool work, F&& f) {
  if (t == nullptr || !work) {
    f();
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  f();
  const auto t1 = std::chrono::steady_clock::now();
  t->ns[k] += std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count();
  ++t->calls[k];
}

}  // namespace xpbd
