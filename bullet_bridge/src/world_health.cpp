// Divergence checks of the systems (SystemSettings::check_health,
// XpbdWorld::health, StepStats::over_stretched / exploded / nonfinite):
// the library's classifier (xpbd/health.hpp) applied after every step, with
// an energy budget kept across steps.
#include <algorithm>
#include <cmath>

#include "world_impl.hpp"
#include "xpbd/constraints.hpp"
#include "xpbd/diagnostics.hpp"

namespace xpbd_bullet {

namespace {

struct Energies {
  double kinetic = 0;    // J, movable particles
  double potential = 0;  // J, gravity, -sum m g.x
  double mass = 0;       // kg, movable particles
};

// masses: the particles' (System::health_mass), filled on first use.
Energies energies(const xpbd::Model& m, std::vector<double>& masses, const xpbd::State& st, const Vec3& g) {
  if (masses.size() != m.inv_mass.size()) {
    masses.resize(m.inv_mass.size());
    for (std::size_t i = 0; i < masses.size(); ++i)
      masses[i] = m.inv_mass[i] > Real(0) ? 1.0 / double(m.inv_mass[i]) : 0.0;
  }
  Energies e;
  for (std::size_t i = 0; i < st.x.size(); ++i) {
    const double mass = masses[i];
    if (!(mass > 0)) continue;  // kinematic: infinite mass, driven
    e.mass += mass;
    e.kinetic += 0.5 * mass * double(st.v[i].squaredNorm());
    e.potential -= mass * double(g.dot(st.x[i]));
  }
  return e;
}

// Speed (m/s) of the point r (body frame) of body b.
double point_speed(const xpbd::RigidBody& b, const Vec3& r) {
  return double((b.v + b.w.cross(b.q * r)).norm());
}

}  // namespace

void XpbdWorld::health_before_solve(System& s, btScalar dt) {
  const xpbd::Model& m = *s.model;
  const xpbd::State& st = s.state;
  const Energies e = energies(m, s.health_mass, st, to_vec(world_.getGravity()));
  if (!s.observed_started) {
    s.observed = {};
    s.observed.kinetic0 = e.kinetic;
    s.observed.potential0 = s.observed.potential_min = e.potential;
    s.observed_started = true;
  } else if (const double added = e.kinetic + e.potential - s.energy_end; added > 0 && std::isfinite(added)) {
    s.edits_input += added;  // the application moved particles or set velocities
  }
  // The fastest point a non-static body touches the system with, and the
  // fastest pin target.
  double v = 0;
  const auto& bodies = st.bodies;
  auto body_point = [&](Index b, const Vec3& r) {
    if (b >= 0 && std::size_t(b) < bodies.size()) v = std::max(v, point_speed(bodies[std::size_t(b)], r));
  };
  for (const xpbd::BodyContact& c : st.contacts) body_point(c.body, c.r);
  for (const xpbd::BodyAttachment& a : st.attachments) body_point(a.body, a.r);
  for (const xpbd::BodyTriangleContact& c : st.triangle_contacts) body_point(c.body, c.r);
  for (const xpbd::BodyEdgeContact& c : st.edge_contacts) {
    body_point(c.body, c.a);
    body_point(c.body, c.b);
  }
  if (s.health_pins.size() == st.pin_target.size() && dt > 0)
    for (std::size_t k = 0; k < st.pin_target.size(); ++k)
      v = std::max(v, double((st.pin_target[k] - s.health_pins[k]).norm()) / double(dt));
  s.health_pins = st.pin_target;
  if (std::isfinite(v)) s.touch_input = std::max(s.touch_input, 2 * e.mass * v * v);
}

void XpbdWorld::health_after_step(System& s) {
  const xpbd::Model& m = *s.model;
  const xpbd::State& st = s.state;
  SystemHealth& h = s.health;
  xpbd::HealthObservation& o = s.observed;
  o.finite = all_finite(st);
  const Energies e = energies(m, s.health_mass, st, to_vec(world_.getGravity()));
  const double strain = double(xpbd::max_distance_strain(m, st));
  // Per step: this step's strain and kinetic energy against the budget so far.
  o.max_strain = strain;
  o.kinetic_max = e.kinetic;
  if (std::isfinite(e.potential)) o.potential_min = std::min(o.potential_min, e.potential);
  o.energy_input = s.edits_input + s.touch_input;
  h.status = xpbd::classify(o, s.settings.health);
  h.max_strain = strain;
  h.kinetic_energy = e.kinetic;
  h.energy_budget = xpbd::energy_budget(o, s.settings.health);
  s.energy_end = e.kinetic + e.potential;
  switch (h.status) {
    case xpbd::Health::over_stretched: ++stats_.over_stretched; break;
    case xpbd::Health::exploded: ++stats_.exploded; break;
    case xpbd::Health::nonfinite: ++stats_.nonfinite; break;
    default: break;
  }
}

}  // namespace xpbd_bullet
