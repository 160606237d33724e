#pragma once
// Is a run (or a system stepped over time) still physics? One classifier
// for the demo runner (metrics.json's "status"), the bridge's step
// statistics (xpbd_bullet::SystemHealth) and the stability map
// (docs/reliability.md, "Divergence is flagged").
//
//   nonfinite       a NaN or Inf in the state, or in a measured quantity;
//   exploded        the kinetic energy exceeds energy_factor times what the
//                   system can have been given (its initial kinetic energy,
//                   the potential energy released since the start, the
//                   energy put in from outside, and a floor), or a particle
//                   got farther than bound + reach outside its initial
//                   bounding box;
//   tunnelled       only where the caller tracks it (the stability map):
//                   something went through a surface;
//   over_stretched  some Distance element's strain |len/rest - 1| exceeds
//                   max_strain;
//   ok              none of these.
//
// Energy conservation bounds the kinetic energy by that budget: solver
// damping and drag only lower it. A run whose kinetic energy exceeds the
// budget many times over has gained energy from the solver.
#include <limits>
#include <ostream>

#include "xpbd/types.hpp"

namespace xpbd {

enum class Health { ok, over_stretched, exploded, nonfinite, tunnelled };
// "ok", "over_stretched", "exploded", "nonfinite", "tunnelled"
const char* health_name(Health h);
inline std::ostream& operator<<(std::ostream& o, Health h) { return o << health_name(h); }

struct HealthThresholds {
  // over_stretched above this largest Distance strain (1 = an edge twice its
  // rest length). Infinity turns the check off.
  double max_strain = 1;
  double energy_factor = 10;   // exploded: kinetic energy > factor x budget (> 1)
  double energy_floor = 1e-3;  // J, added to the budget (a system starting at rest)
  // m: exploded if a particle gets farther than bound + reach outside its
  // initial bounding box. Infinity (the default) turns the check off.
  double bound = std::numeric_limits<double>::infinity();
};

// What a run produced so far.
struct HealthObservation {
  bool finite = true;
  double max_strain = 0;     // 1, largest Distance strain seen
  double kinetic0 = 0;       // J, kinetic energy at the start
  double potential0 = 0;     // J, gravity potential energy at the start
  double potential_min = 0;  // J, smallest potential energy seen
  double kinetic_max = 0;    // J, largest kinetic energy seen
  // J, energy put in from outside since the start (moving bodies and pins,
  // a host's changes to the state): added to the budget.
  double energy_input = 0;
  double max_escape = 0;  // m, largest distance of a particle outside the initial bounding box
  // m, how far a particle can get without energy from the solver (e.g. the
  // ballistic reach v0 T + |g| T^2 / 2 over the run's duration T).
  double reach = 0;
  int tunnelled = 0;  // crossings the caller counted (0 where not tracked)
};

// kinetic0 + max(0, potential0 - potential_min) + energy_input + energy_floor (J).
double energy_budget(const HealthObservation& o, const HealthThresholds& t);

// Order of precedence: nonfinite, exploded (energy), tunnelled, exploded
// (distance bound), over_stretched, ok.
Health classify(const HealthObservation& o, const HealthThresholds& t = {});

// Checks t; throws ConfigError naming the field ("max_strain" > 0,
// "energy_factor" > 1 and finite, "energy_floor" > 0 and finite, "bound" >= 0;
// NaN nowhere) and prefixed with `where` (e.g. "solver.").
void validate(const HealthThresholds& t, const char* where = "");

}  // namespace xpbd
