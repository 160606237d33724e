#include "xpbd/compile.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "xpbd/error.hpp"
#include "xpbd/state.hpp"

namespace xpbd {
namespace {

std::string num(Real v) {
  std::ostringstream o;
  o.precision(9);
  o << v;
  return o.str();
}

// Built with a stream: GCC 12 warns falsely (-Wrestrict, GCC bug 105329) on
// "literal" + std::string&& chains.
std::string vec(const Vec3& v) {
  std::ostringstream o;
  o.precision(9);
  o << '(' << v.x() << ", " << v.y() << ", " << v.z() << ')';
  return o.str();
}

[[noreturn]] void fail(const std::string& where, const std::string& field, const std::string& what) {
  throw SceneError(where + "." + field + ": " + what);
}

std::string at(const char* array, std::size_t i) {
  return std::string(array) + "[" + std::to_string(i) + "]";
}

void check_index(const std::string& where, const char* field, Index i, Index n) {
  if (i < 0 || i >= n)
    fail(where, field, "index " + std::to_string(i) + " out of range [0, " + std::to_string(n) + ")");
}

void check_material(const std::string& where, const Material& m) {
  if (!(m.compliance >= Real(0)) || !std::isfinite(m.compliance))
    fail(where, "mat.compliance", "must be finite and >= 0, got " + num(m.compliance));
  if (!(m.damping >= Real(0)) || !std::isfinite(m.damping))
    fail(where, "mat.damping", "must be finite and >= 0, got " + num(m.damping));
  if (!(m.stiffness >= Real(0) && m.stiffness <= Real(1)))
    fail(where, "mat.stiffness", "must be in [0, 1], got " + num(m.stiffness));
}

void check_distinct(const std::string& where, Index a, Index b) {
  if (a == b) fail(where, "b", "duplicate particle " + std::to_string(a) + " (same as a)");
}

}  // namespace

Index SceneDesc::add_particle(const Vec3& x, Real mass, Real radius, const Vec3& v) {
  const std::size_t n = positions.size();
  positions.push_back(x);
  masses.push_back(mass);
  if (!v.isZero() && velocities.empty()) velocities.assign(n, Vec3::Zero());
  if (!velocities.empty()) velocities.push_back(v);
  if (radius != Real(0) && radii.empty()) radii.assign(n, Real(0));
  if (!radii.empty()) radii.push_back(radius);
  return static_cast<Index>(n);
}

Model compile(const SceneDesc& s) {
  Model m;
  const Index n = s.num_particles();
  const auto un = static_cast<std::size_t>(n);

  // Particles.
  if (s.masses.size() != un)
    fail("scene", "masses", "has " + std::to_string(s.masses.size()) + " entries, positions has " +
                                std::to_string(un));
  if (!s.velocities.empty() && s.velocities.size() != un)
    fail("scene", "velocities", "has " + std::to_string(s.velocities.size()) +
                                    " entries, expected 0 or " + std::to_string(un));
  if (!s.radii.empty() && s.radii.size() != un)
    fail("scene", "radii", "has " + std::to_string(s.radii.size()) + " entries, expected 0 or " +
                               std::to_string(un));
  m.inv_mass.resize(un);
  m.radius.assign(un, Real(0));
  m.x0 = s.positions;
  m.v0 = s.velocities.empty() ? std::vector<Vec3>(un, Vec3::Zero()) : s.velocities;
  for (std::size_t i = 0; i < un; ++i) {
    const std::string w = at("particles", i);
    if (!s.positions[i].allFinite()) fail(w, "position", "must be finite, got " + vec(s.positions[i]));
    const Real mass = s.masses[i];
    if (!std::isfinite(mass) || mass < Real(0))
      fail(w, "mass", "must be finite and >= 0 (0 = kinematic), got " + num(mass));
    m.inv_mass[i] = mass > Real(0) ? Real(1) / mass : Real(0);
    if (!m.v0[i].allFinite()) fail(w, "velocity", "must be finite, got " + vec(m.v0[i]));
    if (!s.radii.empty()) {
      const Real r = s.radii[i];
      if (!std::isfinite(r) || r < Real(0)) fail(w, "radius", "must be finite and >= 0, got " + num(r));
      m.radius[i] = r;
    }
  }

  // Distances.
  auto& dist = m.get<Distance>();
  dist.reserve(s.distances.size());
  for (std::size_t k = 0; k < s.distances.size(); ++k) {
    const auto& d = s.distances[k];
    const std::string w = at("distances", k);
    check_index(w, "a", d.a, n);
    check_index(w, "b", d.b, n);
    check_distinct(w, d.a, d.b);
    check_material(w, d.mat);
    Real rest;
    if (d.rest) {
      rest = *d.rest;
      if (!std::isfinite(rest) || !(rest > Real(0)))
        fail(w, "rest", "must be finite and > 0, got " + num(rest));
    } else {
      rest = (s.positions[d.a] - s.positions[d.b]).norm();
      if (!(rest > Real(0)))
        fail(w, "rest", "particles " + std::to_string(d.a) + " and " + std::to_string(d.b) +
                            " coincide, so the rest length would be 0");
    }
    dist.push_back(Distance{{d.a, d.b}, rest, d.mat});
  }

  // Explicit collision pairs.
  auto& col = m.get<Collision>();
  col.reserve(s.collisions.size());
  for (std::size_t k = 0; k < s.collisions.size(); ++k) {
    const auto& c = s.collisions[k];
    const std::string w = at("collisions", k);
    check_index(w, "a", c.a, n);
    check_index(w, "b", c.b, n);
    check_distinct(w, c.a, c.b);
    check_material(w, c.mat);
    const Real rest = m.radius[c.a] + m.radius[c.b];
    if (!(rest > Real(0)))
      fail(w, "rest", "particles " + std::to_string(c.a) + " and " + std::to_string(c.b) +
                          " both have radius 0, so the contact distance would be 0");
    col.push_back(Collision{{c.a, c.b}, rest, c.mat});
  }

  // Planes: one Wall element per (plane, movable particle).
  auto& walls = m.get<Wall>();
  for (std::size_t k = 0; k < s.planes.size(); ++k) {
    const auto& p = s.planes[k];
    const std::string w = at("planes", k);
    const Real len = p.normal.norm();
    if (!p.normal.allFinite() || !(len > Real(0)))
      fail(w, "normal", "must be finite and non-zero, got " + vec(p.normal));
    if (!std::isfinite(p.offset)) fail(w, "offset", "must be finite, got " + num(p.offset));
    check_material(w, p.mat);
    m.planes.push_back(Plane{p.normal / len, p.offset});
    for (Index i = 0; i < n; ++i)
      if (m.inv_mass[i] > Real(0))
        walls.push_back(Wall{{i}, static_cast<Index>(k), m.radius[i], p.mat});
  }

  // Pins.
  auto& pins = m.get<Pin>();
  pins.reserve(s.pins.size());
  for (std::size_t k = 0; k < s.pins.size(); ++k) {
    const auto& p = s.pins[k];
    const std::string w = at("pins", k);
    check_index(w, "particle", p.particle, n);
    check_material(w, p.mat);
    const Vec3 target = p.target ? *p.target : s.positions[p.particle];
    if (!target.allFinite()) fail(w, "target", "must be finite, got " + vec(target));
    pins.push_back(Pin{{p.particle}, p.mat});
    m.pin_target0.push_back(target);
  }

  for_each_constraint_type([&]<class T>(std::type_identity<T>) {
    bool any = false;
    for (const T& c : m.get<T>()) any = any || c.mat.damping != Real(0);
    m.has_damping[type_index_v<T>] = any;
  });
  return m;
}

State make_state(const Model& m) {
  State s;
  s.x = m.x0;
  s.x_prev = m.x0;
  s.v = m.v0;
  s.pin_target = m.pin_target0;
  s.pin_target_prev = m.pin_target0;
  s.pin_target_now = m.pin_target0;
  for_each_constraint_type([&]<class T>(std::type_identity<T>) {
    s.lambdas<T>().assign(m.get<T>().size(), Real(0));
  });
  return s;
}

}  // namespace xpbd
