#pragma once
// StepConfig::refresh_contacts inside step() (step.cpp): each particle's
// straight path over the step, and the particles that leave it by more than
// StepConfig::contact_margin after a substep's prediction.
#include "xpbd/model.hpp"
#include "xpbd/state.hpp"
#include "xpbd/step.hpp"

namespace xpbd::detail {

// Every particle's path starts at the step's start (State::path_x, path_v,
// path_t).
void begin_paths(const Model& m, State& s);

// The movable particles whose predicted position (the end of substep `sub`)
// is farther than the margin from their path, passed to cfg.refresh_contacts
// in increasing order; their paths restart at the substep's start. Returns
// whether any was passed.
bool refresh_escaped(const Model& m, State& s, const StepConfig& cfg, int sub, Real h);

}  // namespace xpbd::detail
