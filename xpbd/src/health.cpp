#include "xpbd/health.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "xpbd/error.hpp"

namespace xpbd {

const char* health_name(Health h) {
  switch (h) {
    case Health::ok: return "ok";
    case Health::over_stretched: return "over_stretched";
    case Health::exploded: return "exploded";
    case Health::nonfinite: return "nonfinite";
    case Health::tunnelled: return "tunnelled";
  }
  return "?";
}

double energy_budget(const HealthObservation& o, const HealthThresholds& t) {
  return o.kinetic0 + std::max(0.0, o.potential0 - o.potential_min) + o.energy_input + t.energy_floor;
}

Health classify(const HealthObservation& o, const HealthThresholds& t) {
  if (!o.finite || !std::isfinite(o.max_strain) || !std::isfinite(o.kinetic_max) || !std::isfinite(o.max_escape) ||
      !std::isfinite(o.potential_min) || !std::isfinite(o.energy_input))
    return Health::nonfinite;
  if (o.kinetic_max > t.energy_factor * energy_budget(o, t)) return Health::exploded;
  // A particle that went through a plate keeps flying (energy is conserved,
  // but it ends far away): the geometric check comes before the bound.
  if (o.tunnelled > 0) return Health::tunnelled;
  if (o.max_escape > t.bound + o.reach) return Health::exploded;
  if (o.max_strain > t.max_strain) return Health::over_stretched;
  return Health::ok;
}

void validate(const HealthThresholds& t, const char* where) {
  auto fail = [&](const char* field, double v, const char* rule) {
    throw ConfigError(std::string(where) + field + ": must be " + rule + ", got " + format_value(v));
  };
  if (!(t.max_strain > 0)) fail("max_strain", t.max_strain, "> 0 (infinity = off)");
  if (!(t.energy_factor > 1) || !std::isfinite(t.energy_factor)) fail("energy_factor", t.energy_factor, "finite and > 1");
  if (!(t.energy_floor > 0) || !std::isfinite(t.energy_floor)) fail("energy_floor", t.energy_floor, "finite and > 0");
  if (!(t.bound >= 0)) fail("bound", t.bound, ">= 0 (infinity = off)");
}

}  // namespace xpbd
