// Reading scene files: the particle system ("soft": particles, generators,
// elements, contacts).
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "demos/scene_file_read.hpp"
#include "xpbd/error.hpp"
#include "xpbd/io/obj.hpp"

namespace xpbd_demos::scene_read {

namespace {

void read_particles(const Ctx& c, const json& v, const std::string& path, xpbd::SceneDesc& s) {
  const Obj o(c, v, path, kParticlesKeys);
  auto vecs = [&](const char* key) {
    std::vector<Vec3> out;
    if (const json* a = o.get(key))
      out = read_list<Vec3>(c, *a, o.at(key),
                            [&](const json& e, const std::string& p) { return read_vec(c, e, p); });
    return out;
  };
  auto reals = [&](const char* key) {
    std::vector<Real> out;
    if (const json* a = o.get(key))
      out = read_list<Real>(c, *a, o.at(key),
                            [&](const json& e, const std::string& p) { return read_real(c, e, p); });
    return out;
  };
  s.positions = vecs("positions");
  s.masses = reals("masses");
  s.velocities = vecs("velocities");
  s.radii = reals("radii");
  const std::size_t n = s.positions.size();
  c.require(s.masses.size() == n, o.at("masses"),
            "has " + std::to_string(s.masses.size()) + " entries, positions has " + std::to_string(n) +
                " (one mass per particle, kg)");
  for (std::size_t i = 0; i < n; ++i)
    c.require(s.masses[i] >= Real(0), child(o.at("masses"), i),
              "must be >= 0 (0 = kinematic), got " + num(s.masses[i]));
  c.require(s.velocities.empty() || s.velocities.size() == n, o.at("velocities"),
            "has " + std::to_string(s.velocities.size()) + " entries, expected 0 (all at rest) or " +
                std::to_string(n));
  c.require(s.radii.empty() || s.radii.size() == n, o.at("radii"),
            "has " + std::to_string(s.radii.size()) + " entries, expected 0 (all 0) or " + std::to_string(n));
  for (std::size_t i = 0; i < s.radii.size(); ++i) non_negative(c, s.radii[i], child(o.at("radii"), i));
}

std::optional<Real> opt_real(const Obj& o, const char* key) {
  if (const json* v = o.get(key)) return read_real(o.ctx(), *v, o.at(key));
  return std::nullopt;
}

xpbd::ClothGridDesc read_cloth(const Ctx& c, const json& v, const std::string& path) {
  const Obj o(c, v, path, kClothKeys);
  xpbd::ClothGridDesc d;
  o.integer("nx", d.nx);
  o.integer("ny", d.ny);
  o.real("size_u", d.size_u);
  o.real("size_v", d.size_v);
  o.vec("origin", d.origin);
  o.vec("u", d.u);
  o.vec("v", d.v);
  o.real("mass", d.mass);
  o.real("radius", d.radius);
  o.material("stretch", d.stretch);
  o.boolean("shear", d.shear);
  o.boolean("shear_both_diagonals", d.shear_both_diagonals);
  o.material("shear_mat", d.shear_mat);
  o.boolean("bend_distance", d.bend_distance);
  o.material("bend_mat", d.bend_mat);
  o.enumeration("hinge_bending", d.hinge_bending, kHinge);
  o.material("hinge_mat", d.hinge_mat);
  o.enumeration("pins", d.pins, kClothPins);
  if (const json* p = o.get("pinned"))
    d.pinned =
        read_list<std::pair<int, int>>(c, *p, o.at("pinned"), [&](const json& e, const std::string& q) {
          const auto ij = read_ints<2>(c, e, q);
          return std::pair<int, int>(ij[0], ij[1]);
        });
  o.enumeration("tethers", d.tethers, kTetherAnchors);
  o.enumeration("tether_metric", d.tether_metric, kTetherMetric);
  o.material("tether_mat", d.tether_mat);
  o.boolean("collision_triangles", d.collision_triangles);
  o.vec("velocity", d.velocity);
  if (const json* p = o.get("particle_masses"))
    d.particle_masses =
        read_list<xpbd::ParticleMass>(c, *p, o.at("particle_masses"), [&](const json& e, const std::string& q) {
          const Obj m(c, e, q, kClothMassKeys);
          xpbd::ParticleMass pm;
          m.integer("i", pm.i);
          m.integer("j", pm.j);
          m.real("mass", pm.mass);
          return pm;
        });
  return d;
}

xpbd::RopeDesc read_rope(const Ctx& c, const json& v, const std::string& path) {
  const Obj o(c, v, path, kRopeKeys);
  xpbd::RopeDesc d;
  o.integer("n", d.n);
  o.vec("start", d.start);
  o.vec("dir", d.dir);
  o.real("spacing", d.spacing);
  o.real("mass", d.mass);
  o.real("radius", d.radius);
  o.boolean("pin_first", d.pin_first);
  o.material("mat", d.mat);
  o.vec("velocity", d.velocity);
  if (const json* p = o.get("particle_masses"))
    d.particle_masses =
        read_list<xpbd::ParticleMass>(c, *p, o.at("particle_masses"), [&](const json& e, const std::string& q) {
          const Obj m(c, e, q, kRopeMassKeys);
          xpbd::ParticleMass pm;
          m.integer("particle", pm.i);
          m.real("mass", pm.mass);
          return pm;
        });
  return d;
}

xpbd::TetBoxDesc read_tet_box(const Ctx& c, const json& v, const std::string& path) {
  const Obj o(c, v, path, kTetBoxKeys);
  xpbd::TetBoxDesc d;
  o.integer("nx", d.nx);
  o.integer("ny", d.ny);
  o.integer("nz", d.nz);
  o.vec("origin", d.origin);
  o.vec("size", d.size);
  o.enumeration("split", d.split, kTetSplit);
  o.real("mass", d.mass);
  o.real("radius", d.radius);
  o.material("volume_mat", d.volume_mat);
  o.real("bulk_modulus", d.bulk_modulus);
  o.boolean("edges", d.edges);
  o.material("edge_mat", d.edge_mat);
  if (const json* p = o.get("pinned"))
    d.pinned = read_list<std::array<int, 3>>(
        c, *p, o.at("pinned"), [&](const json& e, const std::string& q) { return read_ints<3>(c, e, q); });
  return d;
}

ObjGenerator read_obj(const Ctx& c, const json& v, const std::string& path) {
  const Obj o(c, v, path, kObjKeys);
  ObjGenerator g;
  const json* p = o.get("path");
  c.require(p != nullptr, path, "missing key \"path\" (the OBJ file, relative to the scene file)");
  g.path = read_string(c, *p, o.at("path"));
  o.boolean("triangulate", g.triangulate);
  xpbd::TriangleMeshDesc& d = g.mesh;
  o.enumeration("kind", d.kind, kMeshKind);
  o.real("scale", d.scale);
  o.vec("offset", d.offset);
  o.real("mass", d.mass);
  o.real("radius", d.radius);
  o.material("edge_mat", d.edge_mat);
  o.enumeration("bending", d.bending, kHinge);
  o.material("bend_mat", d.bend_mat);
  o.real("pressure", d.pressure);
  o.material("volume_mat", d.volume_mat);
  return g;
}

SoftContactSpec read_contacts(const Ctx& c, const json& v, const std::string& path) {
  const Obj o(c, v, path, kContactsKeys);
  SoftContactSpec s;
  o.real("thickness", s.thickness);
  non_negative(c, s.thickness, o.at("thickness"));
  o.real("margin", s.margin);
  non_negative(c, s.margin, o.at("margin"));
  o.real("static_friction", s.static_friction);
  non_negative(c, s.static_friction, o.at("static_friction"));
  o.real("dynamic_friction", s.dynamic_friction);
  non_negative(c, s.dynamic_friction, o.at("dynamic_friction"));
  c.require(s.dynamic_friction <= s.static_friction, o.at("dynamic_friction"),
            "must be <= static_friction (" + num(s.static_friction) + "), got " + num(s.dynamic_friction));
  o.real("restitution", s.restitution);
  unit_interval(c, s.restitution, o.at("restitution"));
  o.real("compliance", s.compliance);
  non_negative(c, s.compliance, o.at("compliance"));
  o.real("feature_spacing", s.feature_spacing);
  positive(c, s.feature_spacing, o.at("feature_spacing"));
  o.boolean("wedges", s.wedges);
  o.boolean("edge_contacts", s.edge_contacts);
  o.boolean("surface_edges", s.surface_edges);
  return s;
}

}  // namespace

SoftSpec read_soft(const Ctx& c, const json& v, const std::string& path) {
  const Obj o(c, v, path, kSoftKeys);
  SoftSpec soft;
  xpbd::SceneDesc& s = soft.particles;
  if (const json* p = o.get("particles")) read_particles(c, *p, o.at("particles"), s);

  // Explicit elements. Index ranges and geometry are checked by
  // xpbd::compile, whose errors are mapped back to these paths.
  // Each reader below checks one element (its own keys) and returns it.
  auto elements = [&](const char* key, auto read_one) {
    using T = decltype(read_one(std::declval<const json&>(), std::string()));
    std::vector<T> out;
    if (const json* a = o.get(key)) out = read_list<T>(c, *a, o.at(key), read_one);
    return out;
  };
  s.distances = elements("distances", [&](const json& e, const std::string& q) {
    const Obj d(c, e, q, kDistanceKeys);
    xpbd::DistanceDesc x;
    d.integer("a", x.a);
    d.integer("b", x.b);
    x.rest = opt_real(d, "rest");
    d.material("mat", x.mat);
    return x;
  });
  s.collisions = elements("collisions", [&](const json& e, const std::string& q) {
    const Obj d(c, e, q, kCollisionKeys);
    xpbd::CollisionDesc x;
    d.integer("a", x.a);
    d.integer("b", x.b);
    d.material("mat", x.mat);
    return x;
  });
  s.pins = elements("pins", [&](const json& e, const std::string& q) {
    const Obj d(c, e, q, kPinKeys);
    xpbd::PinDesc x;
    d.integer("particle", x.particle);
    if (const json* t = d.get("target")) x.target = read_vec(c, *t, d.at("target"));
    d.material("mat", x.mat);
    return x;
  });
  s.planes = elements("planes", [&](const json& e, const std::string& q) {
    const Obj d(c, e, q, kPlaneKeys);
    xpbd::PlaneDesc x;
    d.vec("normal", x.normal);
    c.require(x.normal.norm() > Real(0), d.at("normal"), "must be non-zero");
    d.real("offset", x.offset);
    d.material("mat", x.mat);
    return x;
  });
  auto p4 = [&](const Obj& d) {
    const json* p = d.get("p");
    c.require(p != nullptr, d.path(), "missing key \"p\" (the element's 4 particle indices)");
    const auto a = read_ints<4>(c, *p, d.at("p"));
    return std::array<Index, 4>{a[0], a[1], a[2], a[3]};
  };
  s.penetrations = elements("penetrations", [&](const json& e, const std::string& q) {
    const Obj d(c, e, q, kPenetrationKeys);
    xpbd::PenetrationDesc x;
    x.p = p4(d);
    x.thickness = opt_real(d, "thickness");
    if (x.thickness) non_negative(c, *x.thickness, d.at("thickness"));
    d.material("mat", x.mat);
    return x;
  });
  s.dihedral_bends = elements("dihedral_bends", [&](const json& e, const std::string& q) {
    const Obj d(c, e, q, kDihedralKeys);
    xpbd::DihedralBendingDesc x;
    x.p = p4(d);
    x.rest_angle = opt_real(d, "rest_angle");
    d.material("mat", x.mat);
    return x;
  });
  s.isometric_bends = elements("isometric_bends", [&](const json& e, const std::string& q) {
    const Obj d(c, e, q, kIsometricKeys);
    xpbd::IsometricBendingDesc x;
    x.p = p4(d);
    d.material("mat", x.mat);
    return x;
  });
  s.tets = elements("tets", [&](const json& e, const std::string& q) {
    const Obj d(c, e, q, kTetKeys);
    xpbd::TetVolumeDesc x;
    x.p = p4(d);
    x.rest_volume = opt_real(d, "rest_volume");
    d.material("mat", x.mat);
    return x;
  });
  s.tethers = elements("tethers", [&](const json& e, const std::string& q) {
    const Obj d(c, e, q, kTetherKeys);
    xpbd::TetherDesc x;
    d.integer("particle", x.particle);
    d.integer("anchor", x.anchor);
    x.length = opt_real(d, "length");
    d.material("mat", x.mat);
    return x;
  });
  auto triangle = [&](const json& e, const std::string& q) {
    const auto t = read_ints<3>(c, e, q);
    return std::array<Index, 3>{t[0], t[1], t[2]};
  };
  s.global_volumes = elements("global_volumes", [&](const json& e, const std::string& q) {
    const Obj d(c, e, q, kGlobalVolumeKeys);
    xpbd::GlobalVolumeDesc x;
    if (const json* t = d.get("triangles"))
      x.triangles = read_list<std::array<Index, 3>>(c, *t, d.at("triangles"), triangle);
    d.real("pressure", x.pressure);
    d.material("mat", x.mat);
    return x;
  });
  if (const json* sc = o.get("self_collision")) {
    const Obj d(c, *sc, o.at("self_collision"), kSelfCollisionKeys);
    d.boolean("enabled", s.self_collision.enabled);
    d.real("distance", s.self_collision.distance);
    d.boolean("skip_connected", s.self_collision.skip_connected);
    d.material("mat", s.self_collision.mat);
  }
  if (const json* t = o.get("collision_triangles"))
    s.collision_triangles = read_list<std::array<Index, 3>>(c, *t, o.at("collision_triangles"), triangle);

  if (const json* g = o.get("generators"))
    soft.generators = read_list<
        Generator>(c, *g, o.at("generators"), [&](const json& e, const std::string& q) -> Generator {
      const std::string kind = single_kind(c, e, q, {"cloth", "rope", "tet_box", "obj"}, "generator kind");
      const std::string p = child(q, kind);
      if (kind == "cloth") return read_cloth(c, e.begin().value(), p);
      if (kind == "rope") return read_rope(c, e.begin().value(), p);
      if (kind == "tet_box") return read_tet_box(c, e.begin().value(), p);
      return read_obj(c, e.begin().value(), p);
    });
  if (const json* ct = o.get("contacts")) soft.contacts = read_contacts(c, *ct, o.at("contacts"));
  return soft;
}

}  // namespace xpbd_demos::scene_read
