#include "demos/scene_spec.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <sstream>
#include <system_error>

#include "xpbd/error.hpp"
#include "xpbd/io/obj.hpp"

namespace xpbd_demos {
namespace {

using xpbd::Index;
using xpbd::Material;
using xpbd::Real;
using xpbd::SceneError;
using xpbd::Vec3;

// Upper bound on the particles a scene may create, so that a typo such as
// `"nx": 100000` is an error instead of an exhausted memory (a 1000 x 1000
// cloth with shear and bending edges already takes about 0.5 GB).
constexpr std::int64_t kMaxParticles = 1000000;

// Upper bounds on a cloth's tethers (scene files only; the library has
// none): the tethers created, and the tether lengths computed. One length
// per pinned particle and grid particle, except for geodesic
// `nearest_pinned`, which takes one shortest-path search from all pins at
// once (one length per particle). `tethers: all_pinned` on a cloth pinned
// along an edge grows as pins x particles: a 180-byte file once asked for
// 0.8 GB. The fuzzer found a 101-byte one (a 1000 x 32 cloth pinned along
// its top edge, geodesic nearest_pinned, then a search per pin) that took
// 8.5 s, and one at the limit (100 x 1000, 1e7 lengths) that took 9.2 s;
// with the single search the latter builds in about 0.2 s (Release), and
// 1e7 straight-line lengths take about 0.15 s.
constexpr std::int64_t kMaxTethers = 1000000;
constexpr std::int64_t kMaxTetherLengths = 10000000;

// Tolerance for "unit length" and "orthogonal" axes given by hand: accepts
// four-digit rounding (0.7071), catches typos.
constexpr double kAxisTol = 1e-3;

std::string num(double v) { return xpbd::format_value(v); }

std::string vec(const Vec3& v) {
  std::ostringstream o;
  o.precision(9);
  o << '[' << v.x() << ", " << v.y() << ", " << v.z() << ']';
  return o.str();
}

// Checks of one generator's fields; `where` is "generators[g].cloth" etc.
struct Checker {
  std::string where;

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    std::string m = where;
    m += '.';
    m += field;
    m += ": ";
    m += what;
    throw SceneError(m);
  }
  void positive(const char* field, Real v) const {
    if (!std::isfinite(v) || !(v > Real(0))) fail(field, "must be finite and > 0, got " + num(v));
  }
  void non_negative(const char* field, Real v) const {
    if (!std::isfinite(v) || !(v >= Real(0))) fail(field, "must be finite and >= 0, got " + num(v));
  }
  void finite(const char* field, const Vec3& v) const {
    if (!v.allFinite()) fail(field, "must be finite, got " + vec(v));
  }
  void unit(const char* field, const Vec3& v) const {
    finite(field, v);
    if (!(std::abs(double(v.norm()) - 1.0) <= kAxisTol))
      fail(field,
           "must be a unit vector (length within 1e-3 of 1), got " + vec(v) + " of length " + num(v.norm()));
  }
  void at_least(const char* field, int v, int lo) const {
    if (v < lo) fail(field, "must be >= " + std::to_string(lo) + ", got " + std::to_string(v));
  }
  void material(const std::string& field, const Material& m) const {
    if (!std::isfinite(m.compliance) || !(m.compliance >= Real(0)))
      fail(field + ".compliance", "must be finite and >= 0, got " + num(m.compliance));
    if (!std::isfinite(m.damping) || !(m.damping >= Real(0)))
      fail(field + ".damping", "must be finite and >= 0, got " + num(m.damping));
    if (!(m.stiffness >= Real(0) && m.stiffness <= Real(1)))
      fail(field + ".stiffness", "must be in [0, 1], got " + num(m.stiffness));
  }
  void count(const char* field, std::int64_t n, std::int64_t before) const {
    if (n + before > kMaxParticles)
      fail(field, "would create " + std::to_string(n) + " particles (" + std::to_string(n + before) +
                      " in the scene); a scene file may create at most " + std::to_string(kMaxParticles));
  }
};

void check_tethers(const Checker& c, const xpbd::ClothGridDesc& d) {
  if (d.tethers == xpbd::TetherAnchors::none) return;
  std::set<std::pair<int, int>> pins(d.pinned.begin(), d.pinned.end());
  switch (d.pins) {
    case xpbd::ClothPins::none: break;
    case xpbd::ClothPins::top_corners: pins.insert({{0, 0}, {d.nx - 1, 0}}); break;
    case xpbd::ClothPins::top_edge:
      for (int i = 0; i < d.nx; ++i) pins.insert({i, 0});
      break;
    case xpbd::ClothPins::all_corners: pins.insert({{0, 0}, {d.nx - 1, 0}, {0, d.ny - 1}, {d.nx - 1, d.ny - 1}}); break;
  }
  const std::int64_t p = std::int64_t(pins.size()), n = std::int64_t(d.nx) * d.ny, movable = n - p;
  const std::int64_t tethers = d.tethers == xpbd::TetherAnchors::all_pinned ? p * movable : movable;
  if (tethers > kMaxTethers)
    c.fail("tethers", "would create " + std::to_string(tethers) + " tethers (" + std::to_string(p) + " pinned x " +
                          std::to_string(movable) + " movable particles); a scene file may create at most " +
                          std::to_string(kMaxTethers) + ": use \"nearest_pinned\" or fewer pinned particles");
  const bool one_search =
      d.tethers == xpbd::TetherAnchors::nearest_pinned && d.tether_metric == xpbd::TetherMetric::geodesic;
  if (!one_search && p * n > kMaxTetherLengths)
    c.fail("tethers", "would compute " + std::to_string(p * n) + " tether lengths (" + std::to_string(p) +
                          " pinned x " + std::to_string(n) + " particles); a scene file may ask for at most " +
                          std::to_string(kMaxTetherLengths) + ": pin fewer particles");
}

void check_cloth(const Checker& c, const xpbd::ClothGridDesc& d, std::int64_t before) {
  c.at_least("nx", d.nx, 2);
  c.at_least("ny", d.ny, 2);
  c.count("nx", std::int64_t(d.nx) * d.ny, before);
  c.positive("size_u", d.size_u);
  c.positive("size_v", d.size_v);
  c.finite("origin", d.origin);
  c.unit("u", d.u);
  c.unit("v", d.v);
  if (!(std::abs(double(d.u.dot(d.v))) <= kAxisTol))
    c.fail("v", "must be orthogonal to u (|u.v| <= 1e-3), got u.v = " + num(d.u.dot(d.v)));
  c.non_negative("mass", d.mass);
  c.non_negative("radius", d.radius);
  c.material("stretch", d.stretch);
  c.material("shear_mat", d.shear_mat);
  c.material("bend_mat", d.bend_mat);
  c.material("hinge_mat", d.hinge_mat);
  c.material("tether_mat", d.tether_mat);
  for (std::size_t k = 0; k < d.pinned.size(); ++k) {
    const auto [i, j] = d.pinned[k];
    if (i < 0 || i >= d.nx || j < 0 || j >= d.ny)
      c.fail("pinned[" + std::to_string(k) + "]",
             "(" + std::to_string(i) + ", " + std::to_string(j) + ") is outside the " + std::to_string(d.nx) +
                 " x " + std::to_string(d.ny) + " grid (i in [0, " + std::to_string(d.nx) + "), j in [0, " +
                 std::to_string(d.ny) + "))");
  }
  check_tethers(c, d);
}

void check_rope(const Checker& c, const xpbd::RopeDesc& d, std::int64_t before) {
  c.at_least("n", d.n, 2);
  c.count("n", d.n, before);
  c.finite("start", d.start);
  c.unit("dir", d.dir);
  c.positive("spacing", d.spacing);
  c.non_negative("mass", d.mass);
  c.non_negative("radius", d.radius);
  c.material("mat", d.mat);
}

void check_tet_box(const Checker& c, const xpbd::TetBoxDesc& d, std::int64_t before) {
  c.at_least("nx", d.nx, 1);
  c.at_least("ny", d.ny, 1);
  c.at_least("nz", d.nz, 1);
  c.count("nx", (std::int64_t(d.nx) + 1) * (std::int64_t(d.ny) + 1) * (std::int64_t(d.nz) + 1), before);
  c.finite("origin", d.origin);
  c.finite("size", d.size);
  for (int a = 0; a < 3; ++a)
    if (!(d.size[a] > Real(0))) c.fail("size", "every component must be > 0, got " + vec(d.size));
  c.non_negative("mass", d.mass);
  c.non_negative("radius", d.radius);
  c.material("volume_mat", d.volume_mat);
  c.non_negative("bulk_modulus", d.bulk_modulus);
  c.material("edge_mat", d.edge_mat);
  for (std::size_t k = 0; k < d.pinned.size(); ++k) {
    const auto [i, j, l] = d.pinned[k];
    if (i < 0 || i > d.nx || j < 0 || j > d.ny || l < 0 || l > d.nz)
      c.fail("pinned[" + std::to_string(k) + "]",
             "(" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(l) +
                 ") is outside the particle grid [0, " + std::to_string(d.nx) + "] x [0, " +
                 std::to_string(d.ny) + "] x [0, " + std::to_string(d.nz) + "]");
  }
}

void check_mesh_desc(const Checker& c, const xpbd::TriangleMeshDesc& d) {
  c.positive("scale", d.scale);
  c.finite("offset", d.offset);
  c.non_negative("mass", d.mass);
  c.non_negative("radius", d.radius);
  c.material("edge_mat", d.edge_mat);
  c.material("bend_mat", d.bend_mat);
  c.positive("pressure", d.pressure);
  c.material("volume_mat", d.volume_mat);
}

// `path` resolved against base_dir; an error naming `field` if it is not a
// readable regular file.
std::filesystem::path resolve_file(const Checker& c, const char* field, const std::string& path,
                                   const std::filesystem::path& base_dir) {
  if (path.empty()) c.fail(field, "is empty; give the path of an OBJ file");
  const std::filesystem::path p = base_dir / path;
  std::error_code ec;
  const auto st = std::filesystem::status(p, ec);
  if (!std::filesystem::exists(st))
    c.fail(field, "cannot open '" + p.string() + "': No such file or directory");
  if (!std::filesystem::is_regular_file(st))
    c.fail(field, "cannot open '" + p.string() + "': not a regular file");
  return p;
}

std::map<std::string, std::size_t> sizes_of(const xpbd::SceneDesc& s) {
  return {{"positions", s.positions.size()},
          {"distances", s.distances.size()},
          {"collisions", s.collisions.size()},
          {"pins", s.pins.size()},
          {"planes", s.planes.size()},
          {"penetrations", s.penetrations.size()},
          {"dihedral_bends", s.dihedral_bends.size()},
          {"isometric_bends", s.isometric_bends.size()},
          {"tets", s.tets.size()},
          {"tethers", s.tethers.size()},
          {"global_volumes", s.global_volumes.size()},
          {"collision_triangles", s.collision_triangles.size()}};
}

}  // namespace

ExpandedSoft expand(const SoftSpec& soft, const std::filesystem::path& base_dir) {
  ExpandedSoft out;
  xpbd::SceneDesc& s = out.scene;
  s = soft.particles;
  if (std::int64_t(s.positions.size()) > kMaxParticles)
    throw SceneError("particles.positions: has " + std::to_string(s.positions.size()) +
                     " particles; a scene file may create at most " + std::to_string(kMaxParticles));

  // Pictures of the explicit part: its surfaces (each triangle once) and its
  // distance constraints.
  std::set<std::array<Index, 3>> seen;
  auto add_triangle = [&](const std::array<Index, 3>& t) {
    std::array<Index, 3> key = t;
    std::sort(key.begin(), key.end());
    if (seen.insert(key).second) out.triangles.push_back(t);
  };
  for (const auto& t : s.collision_triangles) add_triangle(t);
  for (const auto& g : s.global_volumes)
    for (const auto& t : g.triangles) add_triangle(t);
  for (const auto& d : s.distances) out.lines.push_back({d.a, d.b});
  out.part_sizes.push_back(sizes_of(s));

  for (std::size_t g = 0; g < soft.generators.size(); ++g) {
    const std::string prefix = "generators[" + std::to_string(g) + "]";
    const std::int64_t before = s.num_particles();
    // Builder errors are named after the builder ("cloth.nx/ny: ..."); the
    // prefix says which generator.
    auto rethrow = [&](const SceneError& e) { throw SceneError(prefix + "." + e.what()); };
    const Generator& gen = soft.generators[g];
    if (const auto* cloth = std::get_if<xpbd::ClothGridDesc>(&gen)) {
      check_cloth(Checker{prefix + ".cloth"}, *cloth, before);
      try {
        const xpbd::ClothGrid grid = xpbd::add_cloth_grid(s, *cloth);
        out.triangles.insert(out.triangles.end(), grid.triangles.begin(), grid.triangles.end());
      } catch (const SceneError& e) {
        rethrow(e);
      }
    } else if (const auto* rope = std::get_if<xpbd::RopeDesc>(&gen)) {
      check_rope(Checker{prefix + ".rope"}, *rope, before);
      try {
        const Index first = xpbd::add_rope(s, *rope);
        for (Index k = 1; k < rope->n; ++k) out.lines.push_back({first + k - 1, first + k});
      } catch (const SceneError& e) {
        rethrow(e);
      }
    } else if (const auto* box = std::get_if<xpbd::TetBoxDesc>(&gen)) {
      check_tet_box(Checker{prefix + ".tet_box"}, *box, before);
      try {
        const xpbd::TetBox b = xpbd::add_tet_box(s, *box);
        out.triangles.insert(out.triangles.end(), b.surface.begin(), b.surface.end());
      } catch (const SceneError& e) {
        rethrow(e);
      }
    } else {
      const auto& obj = std::get<ObjGenerator>(gen);
      const Checker c{prefix + ".obj"};
      const std::filesystem::path file = resolve_file(c, "path", obj.path, base_dir);
      check_mesh_desc(c, obj.mesh);
      try {
        const xpbd::TriangleMesh mesh = xpbd::io::load_obj(file.string(), {obj.triangulate});
        c.count("path", std::int64_t(mesh.positions.size()), before);
        xpbd::TriangleMeshDesc d = obj.mesh;
        d.name = file.string();
        d.index_base = 1;  // OBJ numbering in messages
        const xpbd::MeshResult r = xpbd::add_triangle_mesh(s, mesh, d);
        out.triangles.insert(out.triangles.end(), r.triangles.begin(), r.triangles.end());
      } catch (const SceneError& e) {
        // ObjError and mesh errors start with the file's path.
        const std::string what = e.what();
        if (what.rfind(prefix, 0) == 0) throw;  // our own count check
        throw SceneError(prefix + ".obj.path: " + what);
      }
    }
    out.part_sizes.push_back(sizes_of(s));
  }
  return out;
}

xpbd::TriangleMesh body_mesh(const ShapeSpec& shape, const std::filesystem::path& base_dir) {
  const Checker c{"shape.mesh"};
  if (shape.kind != ShapeKind::mesh) throw SceneError("shape: is not a mesh shape");
  c.positive("scale", shape.scale);
  xpbd::TriangleMesh m;
  if (!shape.mesh_file.empty()) {
    if (!shape.vertices.empty() || !shape.triangles.empty())
      c.fail("path", "give either an OBJ file or vertices and triangles, not both");
    const std::filesystem::path file = resolve_file(c, "path", shape.mesh_file, base_dir);
    // Static collision geometry: polygons may be split into triangles.
    m = xpbd::io::load_obj(file.string(), xpbd::io::ObjOptions{true});
  } else {
    if (shape.vertices.empty()) c.fail("vertices", "is empty; give vertices and triangles, or an OBJ path");
    if (shape.triangles.empty()) c.fail("triangles", "is empty; a mesh needs at least one triangle");
    m.positions = shape.vertices;
    const auto nv = static_cast<Index>(m.positions.size());
    for (std::size_t v = 0; v < m.positions.size(); ++v)
      c.finite(("vertices[" + std::to_string(v) + "]").c_str(), m.positions[v]);
    for (std::size_t t = 0; t < shape.triangles.size(); ++t) {
      const auto& tri = shape.triangles[t];
      for (int k = 0; k < 3; ++k)
        if (tri[k] < 0 || tri[k] >= nv)
          c.fail("triangles[" + std::to_string(t) + "][" + std::to_string(k) + "]",
                 "index " + std::to_string(tri[k]) + " out of range [0, " + std::to_string(nv) + ")");
      if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
        c.fail("triangles[" + std::to_string(t) + "]", "repeats a vertex: [" + std::to_string(tri[0]) + ", " +
                                                           std::to_string(tri[1]) + ", " +
                                                           std::to_string(tri[2]) + "]");
      m.triangles.push_back({tri[0], tri[1], tri[2]});
    }
  }
  for (Vec3& p : m.positions) p *= shape.scale;
  return m;
}

}  // namespace xpbd_demos
