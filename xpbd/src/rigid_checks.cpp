// The checks of the rigid-body input (rigid_checks.hpp).
#include "rigid_checks.hpp"

#include <cmath>
#include <string>

#include "xpbd/error.hpp"

namespace xpbd::rigid::detail {

namespace {

std::string at(const char* what, std::size_t k, const char* field) {
  return std::string("state.") + what + "[" + std::to_string(k) + "]." + field;
}

bool nonneg(Real v) { return v >= Real(0) && std::isfinite(v); }

}  // namespace

void check_bodies(const State& s, std::size_t from) {
  for (std::size_t k = from; k < s.bodies.size(); ++k) {
    const RigidBody& b = s.bodies[k];
    if (!(b.inv_mass >= Real(0)) || !std::isfinite(b.inv_mass) || !b.inv_inertia.allFinite() ||
        (b.inv_inertia.array() < Real(0)).any() || !b.x.allFinite() || !b.v.allFinite() ||
        !b.w.allFinite() || !b.q.coeffs().allFinite() || !b.accel.allFinite() ||
        !b.ang_accel.allFinite())
      throw ConfigError("state.bodies[" + std::to_string(k) +
                        "]: pose, velocities, accelerations and inverse mass/inertia must be "
                        "finite and inverse mass/inertia >= 0");
  }
}

void check_index(const Model& m, const State& s, const char* what, std::size_t k, Index p, Index b) {
  const Index np = m.num_particles();
  const auto nb = static_cast<Index>(s.bodies.size());
  if (p < 0 || p >= np)
    throw ConfigError(std::string("state.") + what + "[" + std::to_string(k) + "].particle: index " +
                      std::to_string(p) + " out of range [0, " + std::to_string(np) + ")");
  if (b >= nb)
    throw ConfigError(std::string("state.") + what + "[" + std::to_string(k) + "].body: index " +
                      std::to_string(b) + " out of range [-1, " + std::to_string(nb) + ")");
}

void check_contact(const Model& m, const State& s, std::size_t k) {
  const BodyContact& c = s.contacts[k];
  check_index(m, s, "contacts", k, c.particle, c.body);
  if (!c.r.allFinite())
    throw ConfigError(at("contacts", k, "r") + ": " + format_vec(c.r) + " must be finite");
  if (!c.n.allFinite() || !(std::abs(c.n.norm() - Real(1)) <= Real(1e-3)))
    throw ConfigError(at("contacts", k, "n") + ": " + format_vec(c.n) + " must be a finite unit vector");
  struct Field {
    const char* name;
    Real value;
  };
  for (const Field& f : {Field{"thickness", c.thickness}, Field{"compliance", c.compliance}})
    if (!nonneg(f.value))
      throw ConfigError(at("contacts", k, f.name) + ": " + format_value(double(f.value)) +
                        " must be finite and >= 0");
  // Friction and restitution <= 0 mean none (the bridge passes the product
  // of its settings and the Bullet object's, whatever their sign); they
  // must be numbers.
  for (const Field& f : {Field{"static_friction", c.static_friction},
                         Field{"dynamic_friction", c.dynamic_friction}, Field{"restitution", c.restitution}})
    if (!std::isfinite(f.value))
      throw ConfigError(at("contacts", k, f.name) + ": " + format_value(double(f.value)) + " must be finite");
}

void check_attachment(const Model& m, const State& s, std::size_t k) {
  const BodyAttachment& a = s.attachments[k];
  check_index(m, s, "attachments", k, a.particle, a.body);
  if (!a.r.allFinite())
    throw ConfigError(at("attachments", k, "r") + ": " + format_vec(a.r) + " must be finite");
  if (!nonneg(a.compliance))
    throw ConfigError(at("attachments", k, "compliance") + ": " + format_value(double(a.compliance)) +
                      " must be finite and >= 0");
}

void check_triangle_contact(const Model& m, const State& s, std::size_t k) {
  const BodyTriangleContact& c = s.triangle_contacts[k];
  for (Index p : c.tri) check_index(m, s, "triangle_contacts", k, p, c.body);
  if (!c.r.allFinite())
    throw ConfigError(at("triangle_contacts", k, "r") + ": " + format_vec(c.r) + " must be finite");
  if (c.side != Real(1) && c.side != Real(-1))
    throw ConfigError(at("triangle_contacts", k, "side") + ": " + format_value(double(c.side)) + " must be +1 or -1");
  if (!nonneg(c.thickness))
    throw ConfigError(at("triangle_contacts", k, "thickness") + ": " + format_value(double(c.thickness)) +
                      " must be finite and >= 0");
  if (!std::isfinite(c.static_friction) || !std::isfinite(c.dynamic_friction))
    throw ConfigError(at("triangle_contacts", k, "static_friction") + " and dynamic_friction: " +
                      format_value(double(c.static_friction)) + ", " + format_value(double(c.dynamic_friction)) +
                      " must be finite");
  if (!(c.reach >= Real(0)) || !nonneg(c.closing_speed))
    throw ConfigError("state.triangle_contacts[" + std::to_string(k) + "]: reach = " + format_value(double(c.reach)) +
                      " must be >= 0 (or infinity) and closing_speed = " + format_value(double(c.closing_speed)) +
                      " finite and >= 0");
}

void check_edge_contact(const Model& m, const State& s, std::size_t k) {
  const BodyEdgeContact& c = s.edge_contacts[k];
  for (Index p : c.p) check_index(m, s, "edge_contacts", k, p, c.body);
  if (!c.a.allFinite() || !c.b.allFinite() || !(c.reach >= Real(0)) || !nonneg(c.closing_speed) ||
      !nonneg(c.thickness) || !c.out.allFinite() || !(std::abs(c.out.squaredNorm() - Real(1)) <= Real(1e-3)))
    throw ConfigError("state.edge_contacts[" + std::to_string(k) +
                      "]: a, b must be finite, out a unit vector, thickness finite and >= 0, reach >= 0 (or "
                      "infinity) and closing_speed finite and >= 0");
  if (!std::isfinite(c.static_friction) || !std::isfinite(c.dynamic_friction))
    throw ConfigError(at("edge_contacts", k, "static_friction") + " and dynamic_friction: " +
                      format_value(double(c.static_friction)) + ", " + format_value(double(c.dynamic_friction)) +
                      " must be finite");
}

void check_world_contact(const State& s, std::size_t k) {
  const BodyWorldContact& c = s.world_contacts[k];
  const auto nb = static_cast<Index>(s.bodies.size());
  if (c.body < 0 || c.body >= nb)
    throw ConfigError("state.world_contacts[" + std::to_string(k) + "].body: index " + std::to_string(c.body) +
                      " out of range [0, " + std::to_string(nb) + ")");
  if (c.other < -1 || c.other >= nb || c.other == c.body)
    throw ConfigError("state.world_contacts[" + std::to_string(k) + "].other: index " + std::to_string(c.other) +
                      " out of range [-1, " + std::to_string(nb) + ") or equal to body");
  if (!c.r.allFinite() || !c.p.allFinite() || !c.n.allFinite() || !nonneg(c.friction) ||
      std::abs(c.n.norm() - Real(1)) > Real(1e-3))
    throw ConfigError("state.world_contacts[" + std::to_string(k) +
                      "]: r, p, n and friction must be finite, n of unit length, friction >= 0");
}

}  // namespace xpbd::rigid::detail
