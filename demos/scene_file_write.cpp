// Writing scene files: a SceneSpec as the format's JSON (to_json) and as
// text with the format's key order and short arrays on one line
// (scene_text). The reader is scene_file.cpp.
#include <algorithm>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include "demos/scene_file.hpp"
#include "demos/scene_file_format.hpp"

namespace xpbd_demos {

namespace {

using namespace scene_format;

// ---------------------------------------------------------------------------
// Writing.

json out_generator(const Generator& g) {
  if (const auto* d = std::get_if<xpbd::ClothGridDesc>(&g)) {
    json pinned = json::array();
    for (const auto& [i, j] : d->pinned) pinned.push_back({i, j});
    json out = {{"cloth",
             {{"nx", d->nx},
              {"ny", d->ny},
              {"size_u", out_real(d->size_u)},
              {"size_v", out_real(d->size_v)},
              {"origin", out_vec(d->origin)},
              {"u", out_vec(d->u)},
              {"v", out_vec(d->v)},
              {"mass", out_real(d->mass)},
              {"radius", out_real(d->radius)},
              {"stretch", out_mat(d->stretch)},
              {"shear", d->shear},
              {"shear_both_diagonals", d->shear_both_diagonals},
              {"shear_mat", out_mat(d->shear_mat)},
              {"bend_distance", d->bend_distance},
              {"bend_mat", out_mat(d->bend_mat)},
              {"hinge_bending", enum_name(kHinge, d->hinge_bending)},
              {"hinge_mat", out_mat(d->hinge_mat)},
              {"pins", enum_name(kClothPins, d->pins)},
              {"pinned", pinned},
              {"tethers", enum_name(kTetherAnchors, d->tethers)},
              {"tether_metric", enum_name(kTetherMetric, d->tether_metric)},
              {"tether_mat", out_mat(d->tether_mat)},
              {"collision_triangles", d->collision_triangles}}}};
    json& cloth = out["cloth"];
    if (d->velocity != Vec3::Zero()) cloth["velocity"] = out_vec(d->velocity);
    if (!d->particle_masses.empty()) {
      json masses = json::array();
      for (const xpbd::ParticleMass& m : d->particle_masses)
        masses.push_back({{"i", m.i}, {"j", m.j}, {"mass", out_real(m.mass)}});
      cloth["particle_masses"] = masses;
    }
    return out;
  }
  if (const auto* d = std::get_if<xpbd::RopeDesc>(&g)) {
    json out = {{"rope",
             {{"n", d->n},
              {"start", out_vec(d->start)},
              {"dir", out_vec(d->dir)},
              {"spacing", out_real(d->spacing)},
              {"mass", out_real(d->mass)},
              {"radius", out_real(d->radius)},
              {"pin_first", d->pin_first},
              {"mat", out_mat(d->mat)}}}};
    json& rope = out["rope"];
    if (d->velocity != Vec3::Zero()) rope["velocity"] = out_vec(d->velocity);
    if (!d->particle_masses.empty()) {
      json masses = json::array();
      for (const xpbd::ParticleMass& m : d->particle_masses)
        masses.push_back({{"particle", m.i}, {"mass", out_real(m.mass)}});
      rope["particle_masses"] = masses;
    }
    return out;
  }
  if (const auto* d = std::get_if<xpbd::TetBoxDesc>(&g)) {
    json pinned = json::array();
    for (const auto& p : d->pinned) pinned.push_back({p[0], p[1], p[2]});
    return {{"tet_box",
             {{"nx", d->nx},
              {"ny", d->ny},
              {"nz", d->nz},
              {"origin", out_vec(d->origin)},
              {"size", out_vec(d->size)},
              {"split", enum_name(kTetSplit, d->split)},
              {"mass", out_real(d->mass)},
              {"radius", out_real(d->radius)},
              {"volume_mat", out_mat(d->volume_mat)},
              {"bulk_modulus", out_real(d->bulk_modulus)},
              {"edges", d->edges},
              {"edge_mat", out_mat(d->edge_mat)},
              {"pinned", pinned}}}};
  }
  const auto& o = std::get<ObjGenerator>(g);
  const xpbd::TriangleMeshDesc& d = o.mesh;
  return {{"obj",
           {{"path", o.path},
            {"triangulate", o.triangulate},
            {"kind", enum_name(kMeshKind, d.kind)},
            {"scale", out_real(d.scale)},
            {"offset", out_vec(d.offset)},
            {"mass", out_real(d.mass)},
            {"radius", out_real(d.radius)},
            {"edge_mat", out_mat(d.edge_mat)},
            {"bending", enum_name(kHinge, d.bending)},
            {"bend_mat", out_mat(d.bend_mat)},
            {"pressure", out_real(d.pressure)},
            {"volume_mat", out_mat(d.volume_mat)}}}};
}

json out_shape(const ShapeSpec& s) {
  switch (s.kind) {
    case ShapeKind::sphere:
      return {{"sphere", {{"radius", out_real(s.radius)}}}};
    case ShapeKind::box:
      return {{"box", {{"half_extents", out_vec(s.half_extents)}}}};
    case ShapeKind::capsule:
      return {{"capsule", {{"radius", out_real(s.radius)}, {"height", out_real(s.height)}}}};
    case ShapeKind::cylinder:
      return {{"cylinder", {{"radius", out_real(s.radius)}, {"height", out_real(s.height)}}}};
    case ShapeKind::plane:
      return {{"plane", {{"normal", out_vec(s.normal)}, {"offset", out_real(s.offset)}}}};
    case ShapeKind::convex_hull: {
      json pts = json::array();
      for (const Vec3& p : s.points) pts.push_back(out_vec(p));
      return {{"convex_hull", {{"points", pts}}}};
    }
    case ShapeKind::mesh: {
      json m = json::object();
      if (!s.mesh_file.empty()) m["path"] = s.mesh_file;
      if (s.mesh_file.empty() || !s.vertices.empty() || !s.triangles.empty()) {
        json vs = json::array(), ts = json::array();
        for (const Vec3& p : s.vertices) vs.push_back(out_vec(p));
        for (const auto& t : s.triangles) ts.push_back({t[0], t[1], t[2]});
        m["vertices"] = vs;
        m["triangles"] = ts;
      }
      m["scale"] = out_real(s.scale);
      return {{"mesh", m}};
    }
  }
  return json::object();
}

json out_soft(const SoftSpec& soft) {
  const xpbd::SceneDesc& s = soft.particles;
  json j;
  json pos = json::array(), mass = json::array(), vel = json::array(), rad = json::array();
  for (const Vec3& x : s.positions) pos.push_back(out_vec(x));
  for (Real m : s.masses) mass.push_back(out_real(m));
  for (const Vec3& v : s.velocities) vel.push_back(out_vec(v));
  for (Real r : s.radii) rad.push_back(out_real(r));
  j["particles"] = {{"positions", pos}, {"masses", mass}, {"velocities", vel}, {"radii", rad}};

  auto list = [&](const char* key, const auto& items, auto write) {
    json a = json::array();
    for (const auto& item : items) a.push_back(write(item));
    j[key] = a;
  };
  list("distances", s.distances, [](const xpbd::DistanceDesc& d) {
    json e{{"a", d.a}, {"b", d.b}, {"mat", out_mat(d.mat)}};
    if (d.rest) e["rest"] = out_real(*d.rest);
    return e;
  });
  list("collisions", s.collisions, [](const xpbd::CollisionDesc& d) {
    return json{{"a", d.a}, {"b", d.b}, {"mat", out_mat(d.mat)}};
  });
  list("pins", s.pins, [](const xpbd::PinDesc& d) {
    json e{{"particle", d.particle}, {"mat", out_mat(d.mat)}};
    if (d.target) e["target"] = out_vec(*d.target);
    return e;
  });
  list("planes", s.planes, [](const xpbd::PlaneDesc& d) {
    return json{{"normal", out_vec(d.normal)}, {"offset", out_real(d.offset)}, {"mat", out_mat(d.mat)}};
  });
  list("penetrations", s.penetrations, [](const xpbd::PenetrationDesc& d) {
    json e{{"p", out_indices(d.p)}, {"mat", out_mat(d.mat)}};
    if (d.thickness) e["thickness"] = out_real(*d.thickness);
    return e;
  });
  list("dihedral_bends", s.dihedral_bends, [](const xpbd::DihedralBendingDesc& d) {
    json e{{"p", out_indices(d.p)}, {"mat", out_mat(d.mat)}};
    if (d.rest_angle) e["rest_angle"] = out_real(*d.rest_angle);
    return e;
  });
  list("isometric_bends", s.isometric_bends, [](const xpbd::IsometricBendingDesc& d) {
    return json{{"p", out_indices(d.p)}, {"mat", out_mat(d.mat)}};
  });
  list("tets", s.tets, [](const xpbd::TetVolumeDesc& d) {
    json e{{"p", out_indices(d.p)}, {"mat", out_mat(d.mat)}};
    if (d.rest_volume) e["rest_volume"] = out_real(*d.rest_volume);
    return e;
  });
  list("tethers", s.tethers, [](const xpbd::TetherDesc& d) {
    json e{{"particle", d.particle}, {"anchor", d.anchor}, {"mat", out_mat(d.mat)}};
    if (d.length) e["length"] = out_real(*d.length);
    return e;
  });
  list("global_volumes", s.global_volumes, [](const xpbd::GlobalVolumeDesc& d) {
    json t = json::array();
    for (const auto& tri : d.triangles) t.push_back(out_indices(tri));
    return json{{"triangles", t}, {"pressure", out_real(d.pressure)}, {"mat", out_mat(d.mat)}};
  });
  j["self_collision"] = {{"enabled", s.self_collision.enabled},
                         {"distance", out_real(s.self_collision.distance)},
                         {"skip_connected", s.self_collision.skip_connected},
                         {"mat", out_mat(s.self_collision.mat)}};
  list("collision_triangles", s.collision_triangles,
       [](const std::array<Index, 3>& t) { return out_indices(t); });
  list("generators", soft.generators, out_generator);
  const SoftContactSpec& c = soft.contacts;
  j["contacts"] = {{"thickness", out_real(c.thickness)},
                   {"margin", out_real(c.margin)},
                   {"static_friction", out_real(c.static_friction)},
                   {"dynamic_friction", out_real(c.dynamic_friction)},
                   {"restitution", out_real(c.restitution)},
                   {"compliance", out_real(c.compliance)},
                   {"feature_spacing", out_real(c.feature_spacing)},
                   {"wedges", c.wedges},
                   {"edge_contacts", c.edge_contacts},
                   {"surface_edges", c.surface_edges}};
  return j;
}

// The keys of `obj` in the order of the format's key list that holds all
// of them (the shortest such list); keys of no list follow alphabetically.
std::vector<std::string> ordered_keys(const json& obj) {
  std::vector<std::string> keys;
  for (const auto& item : obj.items()) keys.push_back(item.key());
  const Keys* best = nullptr;
  for (const Keys* list : all_key_lists()) {
    const bool all = std::all_of(keys.begin(), keys.end(), [&](const std::string& k) {
      return std::find_if(list->begin(), list->end(), [&](const char* l) { return k == l; }) != list->end();
    });
    if (all && (!best || list->size() < best->size())) best = list;
  }
  if (!best) return keys;  // std::map order: alphabetical
  auto rank = [&](const std::string& k) {
    return std::find_if(best->begin(), best->end(), [&](const char* l) { return k == l; }) - best->begin();
  };
  std::stable_sort(keys.begin(), keys.end(),
                   [&](const std::string& a, const std::string& b) { return rank(a) < rank(b); });
  return keys;
}

// Nesting depth: 0 for a scalar, 1 + the deepest element for a container.
int depth(const json& j) {
  if (!j.is_object() && !j.is_array()) return 0;
  int d = 0;
  for (const auto& e : j) d = std::max(d, depth(e));
  return d + 1;
}

// One line: {"compliance": 1e-06, "damping": 0.0, "stiffness": 1.0}.
std::string one_line(const json& j) {
  std::string out;
  if (j.is_object()) {
    out += '{';
    bool first = true;
    for (const std::string& k : ordered_keys(j)) {
      out += (first ? "" : ", ") + json(k).dump() + ": " + one_line(j.at(k));
      first = false;
    }
    out += '}';
  } else if (j.is_array()) {
    out += '[';
    for (std::size_t i = 0; i < j.size(); ++i) out += (i ? ", " : "") + one_line(j[i]);
    out += ']';
  } else {
    out += j.dump();
  }
  return out;
}

constexpr std::size_t kTextWidth = 100;

// `column`: where the value starts on its line (after the key).
void write_text(std::string& out, const json& j, std::size_t indent, std::size_t column) {
  // A scalar (number, string, ...) as it is, however long.
  if (!j.is_structured()) {
    out += j.dump();
    return;
  }
  // Small values (materials, vectors, elements, short lists) on one line.
  if (depth(j) <= 3) {
    const std::string line = one_line(j);
    if (column + line.size() <= kTextWidth) {
      out += line;
      return;
    }
  }
  const std::string pad(indent + 2, ' ');
  if (j.is_object()) {
    out += "{\n";
    const std::vector<std::string> keys = ordered_keys(j);
    for (std::size_t i = 0; i < keys.size(); ++i) {
      const std::string key = json(keys[i]).dump() + ": ";
      out += pad + key;
      write_text(out, j.at(keys[i]), indent + 2, pad.size() + key.size());
      out += i + 1 < keys.size() ? ",\n" : "\n";
    }
    out += std::string(indent, ' ') + "}";
  } else if (std::all_of(j.begin(), j.end(), [](const json& e) { return depth(e) == 0; })) {
    // A long array of scalars: wrapped.
    out += "[";
    std::size_t col = column + 1;
    for (std::size_t i = 0; i < j.size(); ++i) {
      const std::string item = j[i].dump() + (i + 1 < j.size() ? "," : "]");
      if (i > 0) {
        if (col + 1 + item.size() > kTextWidth) {
          out += "\n" + pad;
          col = pad.size();
        } else {
          out += ' ';
          ++col;
        }
      }
      out += item;
      col += item.size();
    }
  } else {
    out += "[\n";
    for (std::size_t i = 0; i < j.size(); ++i) {
      out += pad;
      write_text(out, j[i], indent + 2, pad.size());
      out += i + 1 < j.size() ? ",\n" : "\n";
    }
    out += std::string(indent, ' ') + "]";
  }
}

}  // namespace

json to_json(const SceneSpec& s) {
  json j;
  j["name"] = s.name;
  j["description"] = s.description;
  const SolverSpec& v = s.solver;
  j["solver"] = {{"method", enum_name(kSolvers, v.method)},
                 {"dt", out_real(v.dt)},
                 {"substeps", v.substeps},
                 {"iterations", v.iterations},
                 {"frames", v.frames},
                 {"drag", out_real(v.drag)},
                 {"alternate_sweeps", v.alternate_sweeps},
                 {"coloured", v.coloured},
                 {"direct_chains", v.direct_chains},
                 {"chain_passes", v.chain_passes},
                 {"chain_tolerance", out_real(v.chain_tolerance)},
                 {"hierarchy", v.hierarchy},
                 {"hierarchy_slack", out_real(v.hierarchy_slack)},
                 {"gravity", out_vec(v.gravity)},
                 {"bullet_kLST", out_real(v.bullet_kLST)},
                 {"max_strain", v.max_strain},
                 {"tolerance", v.tolerance},
                 {"tolerance_measure", enum_name(kToleranceMeasures, v.tolerance_measure)},
                 {"penetration_tolerance", v.penetration_tolerance},
                 {"max_substeps", v.max_substeps}};
  j["soft"] = out_soft(s.soft);
  json bodies = json::array();
  for (const RigidSpec& b : s.bodies) {
    json q = json::array();
    for (Real x : b.orientation) q.push_back(out_real(x));
    bodies.push_back({{"name", b.name},
                      {"shape", out_shape(b.shape)},
                      {"mass", out_real(b.mass)},
                      {"position", out_vec(b.position)},
                      {"orientation", q},
                      {"velocity", out_vec(b.velocity)},
                      {"angular_velocity", out_vec(b.angular_velocity)},
                      {"friction", out_real(b.friction)},
                      {"restitution", out_real(b.restitution)},
                      {"linear_damping", out_real(b.linear_damping)},
                      {"angular_damping", out_real(b.angular_damping)},
                      {"kinematic", b.kinematic}});
  }
  j["bodies"] = bodies;
  json att = json::array();
  for (const AttachmentSpec& a : s.attachments) {
    json e{{"particle", a.particle}, {"body", a.body}, {"compliance", out_real(a.compliance)}};
    if (a.local) e["local"] = out_vec(*a.local);
    att.push_back(e);
  }
  j["attachments"] = att;
  return j;
}

std::string scene_text(const json& j) {
  std::string out;
  write_text(out, j, 0, 0);
  out += '\n';
  return out;
}

}  // namespace xpbd_demos
