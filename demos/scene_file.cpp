#include "demos/scene_file.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <string_view>
#include <type_traits>

#include "xpbd/compile.hpp"
#include "xpbd/error.hpp"
#include "xpbd/io/obj.hpp"

namespace xpbd_demos {

SceneFileError::SceneFileError(std::string file, std::string json_path, std::string reason)
    : std::runtime_error(file + ": " + (json_path.empty() ? std::string() : json_path + ": ") + reason),
      file_(std::move(file)),
      path_(std::move(json_path)),
      reason_(std::move(reason)) {}

namespace {

using json = nlohmann::json;
using xpbd::Index;
using xpbd::Material;
using xpbd::Real;
using xpbd::Vec3;

// ---------------------------------------------------------------------------
// Enum names.

template <class E>
struct EnumName {
  const char* name;
  E value;
};

constexpr EnumName<Solver> kSolvers[] = {
    {"xpbd", Solver::xpbd}, {"pbd", Solver::pbd}, {"bullet", Solver::bullet}};
constexpr EnumName<xpbd::HingeBending> kHinge[] = {{"none", xpbd::HingeBending::none},
                                                   {"dihedral", xpbd::HingeBending::dihedral},
                                                   {"isometric", xpbd::HingeBending::isometric}};
constexpr EnumName<xpbd::ClothPins> kClothPins[] = {{"none", xpbd::ClothPins::none},
                                                    {"top_corners", xpbd::ClothPins::top_corners},
                                                    {"top_edge", xpbd::ClothPins::top_edge},
                                                    {"all_corners", xpbd::ClothPins::all_corners}};
constexpr EnumName<xpbd::TetherAnchors> kTetherAnchors[] = {
    {"none", xpbd::TetherAnchors::none},
    {"all_pinned", xpbd::TetherAnchors::all_pinned},
    {"nearest_pinned", xpbd::TetherAnchors::nearest_pinned}};
constexpr EnumName<xpbd::TetherMetric> kTetherMetric[] = {{"euclidean", xpbd::TetherMetric::euclidean},
                                                          {"geodesic", xpbd::TetherMetric::geodesic}};
constexpr EnumName<xpbd::TetSplit> kTetSplit[] = {{"five", xpbd::TetSplit::five},
                                                  {"six", xpbd::TetSplit::six}};
constexpr EnumName<xpbd::MeshKind> kMeshKind[] = {{"cloth", xpbd::MeshKind::cloth},
                                                  {"closed_surface", xpbd::MeshKind::closed_surface}};

template <class E, std::size_t N>
const char* enum_name(const EnumName<E> (&table)[N], E v) {
  for (const auto& e : table)
    if (e.value == v) return e.name;
  return "?";
}

// ---------------------------------------------------------------------------
// Small helpers.

std::string num(double v) { return xpbd::format_value(v); }

// A JSON value as it appears in a message, shortened.
std::string show(const json& v) {
  std::string s = v.dump();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

// One JSON pointer token (RFC 6901: "~" -> "~0", "/" -> "~1").
std::string token(std::string_view key) {
  std::string t;
  for (char ch : key) {
    if (ch == '~')
      t += "~0";
    else if (ch == '/')
      t += "~1";
    else
      t += ch;
  }
  return t;
}

std::string child(const std::string& path, std::string_view key) { return path + "/" + token(key); }
std::string child(const std::string& path, std::size_t i) { return path + "/" + std::to_string(i); }

// A Real as a JSON number that parses back to exactly the same Real. For a
// float, the shortest decimal that reads back as that float (0.1f is
// written 0.1, not 0.100000001490116), unless reading it as a double and
// rounding to float could land elsewhere; then the exact double value.
double out_real(Real v) {
  if constexpr (std::is_same_v<Real, float>) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    double d = 0;
    std::from_chars(buf, r.ptr, d);
    if (static_cast<float>(d) == v || (std::isnan(v) && std::isnan(d))) return d;
    return static_cast<double>(v);
  } else {
    return v;
  }
}

json out_vec(const Vec3& v) { return json::array({out_real(v.x()), out_real(v.y()), out_real(v.z())}); }

json out_mat(const Material& m) {
  return json{{"compliance", out_real(m.compliance)},
              {"damping", out_real(m.damping)},
              {"stiffness", out_real(m.stiffness)}};
}

template <std::size_t N>
json out_indices(const std::array<Index, N>& p) {
  json a = json::array();
  for (Index i : p) a.push_back(i);
  return a;
}

// ---------------------------------------------------------------------------
// The keys of every object of the format, in the order the format lists
// them (docs/scene-format.md): the parser accepts exactly these, and
// scene_text writes keys in this order.

// Constant-initialised (no static initialisation order to worry about).
using Keys = std::initializer_list<const char*>;
// clang-format off
constexpr Keys kTopKeys{"name", "description", "solver", "soft", "bodies", "attachments"};
constexpr Keys kSolverKeys{"method", "dt", "substeps", "iterations", "frames", "drag", "alternate_sweeps",
                           "coloured", "gravity", "bullet_kLST", "max_strain",
                           "tolerance", "max_substeps"};
constexpr Keys kSoftKeys{"particles", "generators", "contacts", "distances", "collisions", "pins", "planes",
                     "penetrations", "dihedral_bends", "isometric_bends", "tets", "tethers",
                     "global_volumes", "self_collision", "collision_triangles"};
constexpr Keys kParticlesKeys{"positions", "masses", "velocities", "radii"};
constexpr Keys kMaterialKeys{"compliance", "damping", "stiffness"};
constexpr Keys kDistanceKeys{"a", "b", "rest", "mat"};
constexpr Keys kCollisionKeys{"a", "b", "mat"};
constexpr Keys kPinKeys{"particle", "target", "mat"};
constexpr Keys kPlaneKeys{"normal", "offset", "mat"};
constexpr Keys kPenetrationKeys{"p", "thickness", "mat"};
constexpr Keys kDihedralKeys{"p", "rest_angle", "mat"};
constexpr Keys kIsometricKeys{"p", "mat"};
constexpr Keys kTetKeys{"p", "rest_volume", "mat"};
constexpr Keys kTetherKeys{"particle", "anchor", "length", "mat"};
constexpr Keys kGlobalVolumeKeys{"triangles", "pressure", "mat"};
constexpr Keys kSelfCollisionKeys{"enabled", "distance", "skip_connected", "mat"};
constexpr Keys kClothKeys{"nx", "ny", "size_u", "size_v", "origin", "u", "v", "mass", "radius", "stretch",
                      "shear", "shear_both_diagonals", "shear_mat", "bend_distance", "bend_mat",
                      "hinge_bending", "hinge_mat", "pins", "pinned", "tethers", "tether_metric",
                      "tether_mat", "collision_triangles"};
constexpr Keys kRopeKeys{"n", "start", "dir", "spacing", "mass", "radius", "pin_first", "mat"};
constexpr Keys kTetBoxKeys{"nx", "ny", "nz", "origin", "size", "split", "mass", "radius", "volume_mat",
                       "bulk_modulus", "edges", "edge_mat", "pinned"};
constexpr Keys kObjKeys{"path", "triangulate", "kind", "scale", "offset", "mass", "radius", "edge_mat",
                    "bending", "bend_mat", "pressure", "volume_mat"};
constexpr Keys kContactsKeys{"thickness", "margin", "static_friction", "dynamic_friction", "restitution",
                         "compliance", "feature_spacing"};
constexpr Keys kBodyKeys{"name", "shape", "mass", "position", "orientation", "velocity", "angular_velocity",
                         "friction", "restitution", "linear_damping", "angular_damping", "kinematic"};
constexpr Keys kSphereKeys{"radius"};
constexpr Keys kBoxKeys{"half_extents"};
constexpr Keys kCapsuleKeys{"radius", "height"};
constexpr Keys kShapePlaneKeys{"normal", "offset"};
constexpr Keys kHullKeys{"points"};
constexpr Keys kMeshKeys{"path", "vertices", "triangles", "scale"};
constexpr Keys kAttachmentKeys{"particle", "body", "local", "compliance"};
// clang-format on

const std::vector<const Keys*>& all_key_lists() {
  static const std::vector<const Keys*> lists = {
      &kTopKeys,           &kSolverKeys,    &kSoftKeys,   &kParticlesKeys, &kMaterialKeys,
      &kDistanceKeys,      &kCollisionKeys, &kPinKeys,    &kPlaneKeys,     &kPenetrationKeys,
      &kDihedralKeys,      &kIsometricKeys, &kTetKeys,    &kTetherKeys,    &kGlobalVolumeKeys,
      &kSelfCollisionKeys, &kClothKeys,     &kRopeKeys,   &kTetBoxKeys,    &kObjKeys,
      &kContactsKeys,      &kBodyKeys,      &kSphereKeys, &kBoxKeys,       &kCapsuleKeys,
      &kShapePlaneKeys,    &kHullKeys,      &kMeshKeys,   &kAttachmentKeys};
  return lists;
}

// ---------------------------------------------------------------------------
// Reading: every function gets the JSON value and its path; errors throw
// SceneFileError(file, path, reason).

struct Ctx {
  std::string file;
  [[noreturn]] void fail(const std::string& path, const std::string& reason) const {
    throw SceneFileError(file, path.empty() ? "/" : path, reason);
  }
  void require(bool ok, const std::string& path, const std::string& reason) const {
    if (!ok) fail(path, reason);
  }
};

Real read_real(const Ctx& c, const json& v, const std::string& path) {
  if (!v.is_number()) c.fail(path, "expected a number, got " + show(v));
  const double d = v.get<double>();
  const Real r = static_cast<Real>(d);
  if (!std::isfinite(r))
    c.fail(path,
           "must be a finite number" +
               std::string(std::is_same_v<Real, float> ? " within the float range (|x| < 3.4e38)" : "") +
               ", got " + show(v));
  return r;
}

int read_int(const Ctx& c, const json& v, const std::string& path) {
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    if (u > std::uint64_t(std::numeric_limits<int>::max()))
      c.fail(path, "integer " + show(v) + " is too large (max " +
                       std::to_string(std::numeric_limits<int>::max()) + ")");
    return static_cast<int>(u);
  }
  if (v.is_number_integer()) {
    const auto i = v.get<std::int64_t>();
    if (i < std::int64_t(std::numeric_limits<int>::min()))
      c.fail(path, "integer " + show(v) + " is too small");
    return static_cast<int>(i);
  }
  c.fail(path, "expected an integer, got " + show(v));
}

bool read_bool(const Ctx& c, const json& v, const std::string& path) {
  if (!v.is_boolean()) c.fail(path, "expected true or false, got " + show(v));
  return v.get<bool>();
}

std::string read_string(const Ctx& c, const json& v, const std::string& path) {
  if (!v.is_string()) c.fail(path, "expected a string, got " + show(v));
  return v.get<std::string>();
}

const json& read_array(const Ctx& c, const json& v, const std::string& path) {
  if (!v.is_array()) c.fail(path, "expected an array [ ... ], got " + show(v));
  return v;
}

Vec3 read_vec(const Ctx& c, const json& v, const std::string& path) {
  if (!v.is_array() || v.size() != 3)
    c.fail(path, "expected [x, y, z] (an array of 3 numbers), got " + show(v));
  return Vec3(read_real(c, v[0], child(path, 0)), read_real(c, v[1], child(path, 1)),
              read_real(c, v[2], child(path, 2)));
}

template <std::size_t N>
std::array<int, N> read_ints(const Ctx& c, const json& v, const std::string& path) {
  if (!v.is_array() || v.size() != N)
    c.fail(path, "expected an array of " + std::to_string(N) + " integers, got " + show(v));
  std::array<int, N> a{};
  for (std::size_t i = 0; i < N; ++i) a[i] = read_int(c, v[i], child(path, i));
  return a;
}

template <class T, class F>
std::vector<T> read_list(const Ctx& c, const json& v, const std::string& path, F&& read_one) {
  read_array(c, v, path);
  std::vector<T> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out.push_back(read_one(v[i], child(path, i)));
  return out;
}

template <class E, std::size_t N>
E read_enum(const Ctx& c, const json& v, const std::string& path, const EnumName<E> (&table)[N]) {
  std::string names;
  for (std::size_t i = 0; i < N; ++i) names += (i ? ", \"" : "\"") + std::string(table[i].name) + "\"";
  if (!v.is_string()) c.fail(path, "expected one of " + names + ", got " + show(v));
  const std::string s = v.get<std::string>();
  for (const auto& e : table)
    if (s == e.name) return e.value;
  c.fail(path, "must be one of " + names + ", got " + show(v));
}

// Range checks.
void positive(const Ctx& c, Real v, const std::string& path) {
  c.require(v > Real(0), path, "must be > 0, got " + num(v));
}
void non_negative(const Ctx& c, Real v, const std::string& path) {
  c.require(v >= Real(0), path, "must be >= 0, got " + num(v));
}
void unit_interval(const Ctx& c, Real v, const std::string& path) {
  c.require(v >= Real(0) && v <= Real(1), path, "must be in [0, 1], got " + num(v));
}
void at_least(const Ctx& c, int v, int lo, const std::string& path) {
  c.require(v >= lo, path, "must be >= " + std::to_string(lo) + ", got " + std::to_string(v));
}

// A JSON object with a fixed set of keys: unknown keys are errors (reported
// before any value is read, since a misspelt key is the likeliest mistake).
class Obj {
 public:
  Obj(const Ctx& c, const json& j, std::string path, const Keys& keys)
      : c_(c), j_(j), path_(std::move(path)), keys_(keys) {
    if (!j.is_object()) c.fail(path_, "expected an object { ... }, got " + show(j));
    for (const auto& item : j.items()) {
      if (std::find_if(keys_.begin(), keys_.end(), [&](const char* k) { return item.key() == k; }) ==
          keys_.end()) {
        std::string list;
        for (const char* k : keys_) list += (list.empty() ? "" : ", ") + std::string(k);
        c.fail(at(item.key()), "unknown key (expected one of: " + list + ")");
      }
    }
  }

  const Ctx& ctx() const { return c_; }
  const std::string& path() const { return path_; }
  std::string at(std::string_view key) const { return child(path_, key); }

  // The value of `key`, or nullptr if absent.
  const json* get(const char* key) const {
    const auto it = j_.find(key);
    return it == j_.end() ? nullptr : &*it;
  }

  // Optional fields: left unchanged when absent.
  void real(const char* key, Real& out) const {
    if (const json* v = get(key)) out = read_real(c_, *v, at(key));
  }
  void integer(const char* key, int& out) const {
    if (const json* v = get(key)) out = read_int(c_, *v, at(key));
  }
  void boolean(const char* key, bool& out) const {
    if (const json* v = get(key)) out = read_bool(c_, *v, at(key));
  }
  void string(const char* key, std::string& out) const {
    if (const json* v = get(key)) out = read_string(c_, *v, at(key));
  }
  void vec(const char* key, Vec3& out) const {
    if (const json* v = get(key)) out = read_vec(c_, *v, at(key));
  }
  void material(const char* key, Material& out) const;
  template <class E, std::size_t N>
  void enumeration(const char* key, E& out, const EnumName<E> (&table)[N]) const {
    if (const json* v = get(key)) out = read_enum(c_, *v, at(key), table);
  }

 private:
  const Ctx& c_;
  const json& j_;
  std::string path_;
  Keys keys_;
};

Material read_material(const Ctx& c, const json& v, const std::string& path) {
  const Obj o(c, v, path, kMaterialKeys);
  Material m;
  o.real("compliance", m.compliance);
  o.real("damping", m.damping);
  o.real("stiffness", m.stiffness);
  non_negative(c, m.compliance, o.at("compliance"));
  non_negative(c, m.damping, o.at("damping"));
  unit_interval(c, m.stiffness, o.at("stiffness"));
  return m;
}

void Obj::material(const char* key, Material& out) const {
  if (const json* v = get(key)) out = read_material(c_, *v, at(key));
}

// An object with exactly one key naming its kind ({"cloth": {...}}); returns
// that key, checked against `kinds`.
std::string single_kind(const Ctx& c, const json& v, const std::string& path,
                        std::initializer_list<const char*> kinds, const char* what) {
  std::string list;
  for (const char* k : kinds) list += (list.empty() ? "" : ", ") + std::string(k);
  if (!v.is_object() || v.size() != 1)
    c.fail(path, std::string("expected an object with exactly one key, the ") + what + " (" + list +
                     "), got " + show(v));
  const std::string kind = v.begin().key();
  if (std::find_if(kinds.begin(), kinds.end(), [&](const char* k) { return kind == k; }) == kinds.end())
    c.fail(child(path, kind), std::string("unknown ") + what + " (expected one of: " + list + ")");
  return kind;
}

// ---------------------------------------------------------------------------
// Sections.

SolverSpec read_solver(const Ctx& c, const json& v, const std::string& path) {
  const Obj o(c, v, path, kSolverKeys);
  SolverSpec s;
  o.enumeration("method", s.method, kSolvers);
  o.real("dt", s.dt);
  positive(c, s.dt, o.at("dt"));
  o.integer("substeps", s.substeps);
  at_least(c, s.substeps, 1, o.at("substeps"));
  o.integer("iterations", s.iterations);
  at_least(c, s.iterations, 1, o.at("iterations"));
  o.integer("frames", s.frames);
  at_least(c, s.frames, 1, o.at("frames"));
  o.real("drag", s.drag);
  non_negative(c, s.drag, o.at("drag"));
  o.boolean("alternate_sweeps", s.alternate_sweeps);
  o.boolean("coloured", s.coloured);
  o.vec("gravity", s.gravity);
  o.real("bullet_kLST", s.bullet_kLST);
  c.require(s.bullet_kLST > Real(0) && s.bullet_kLST <= Real(1), o.at("bullet_kLST"),
            "must be in (0, 1], got " + num(s.bullet_kLST));
  Real max_strain = Real(s.max_strain);
  o.real("max_strain", max_strain);
  positive(c, max_strain, o.at("max_strain"));
  s.max_strain = double(max_strain);
  Real tolerance = Real(s.tolerance);
  o.real("tolerance", tolerance);
  non_negative(c, tolerance, o.at("tolerance"));
  s.tolerance = double(tolerance);
  o.integer("max_substeps", s.max_substeps);
  at_least(c, s.max_substeps, 1, o.at("max_substeps"));
  return s;
}

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
  return s;
}

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

// Four points that span a volume (relative to the points' extent), i.e. not
// all on one plane.
bool spans_volume(const std::vector<Vec3>& pts) {
  const Vec3& a = pts[0];
  std::size_t ib = 0;
  for (std::size_t i = 1; i < pts.size(); ++i)
    if ((pts[i] - a).squaredNorm() > (pts[ib] - a).squaredNorm()) ib = i;
  const Vec3 ab = pts[ib] - a;
  const double len = ab.norm();
  if (!(len > 0)) return false;
  std::size_t ic = 0;
  for (std::size_t i = 1; i < pts.size(); ++i)
    if (ab.cross(pts[i] - a).squaredNorm() > ab.cross(pts[ic] - a).squaredNorm()) ic = i;
  const Vec3 n = ab.cross(pts[ic] - a);
  if (!(double(n.norm()) > 1e-6 * len * len)) return false;
  double h = 0;
  for (const Vec3& p : pts) h = std::max(h, std::abs(double(n.normalized().dot(p - a))));
  // Tolerance relative to the extent: 1e-6 is far above round-off in float
  // (1.2e-7) and far below any intended thickness.
  return h > 1e-6 * len;
}

ShapeSpec read_shape(const Ctx& c, const json& v, const std::string& path) {
  const std::string kind = single_kind(
      c, v, path, {"sphere", "box", "capsule", "cylinder", "plane", "convex_hull", "mesh"}, "shape kind");
  const json& body = v.begin().value();
  const std::string p = child(path, kind);
  ShapeSpec s;
  if (kind == "sphere") {
    s.kind = ShapeKind::sphere;
    const Obj o(c, body, p, kSphereKeys);
    o.real("radius", s.radius);
    positive(c, s.radius, o.at("radius"));
  } else if (kind == "box") {
    s.kind = ShapeKind::box;
    const Obj o(c, body, p, kBoxKeys);
    o.vec("half_extents", s.half_extents);
    for (int a = 0; a < 3; ++a) positive(c, s.half_extents[a], child(o.at("half_extents"), std::size_t(a)));
  } else if (kind == "capsule" || kind == "cylinder") {
    s.kind = kind == "capsule" ? ShapeKind::capsule : ShapeKind::cylinder;
    const Obj o(c, body, p, kCapsuleKeys);
    o.real("radius", s.radius);
    positive(c, s.radius, o.at("radius"));
    o.real("height", s.height);
    if (s.kind == ShapeKind::capsule)
      non_negative(c, s.height, o.at("height"));
    else
      positive(c, s.height, o.at("height"));
  } else if (kind == "plane") {
    s.kind = ShapeKind::plane;
    const Obj o(c, body, p, kShapePlaneKeys);
    o.vec("normal", s.normal);
    c.require(s.normal.norm() > Real(0), o.at("normal"), "must be non-zero");
    o.real("offset", s.offset);
  } else if (kind == "convex_hull") {
    s.kind = ShapeKind::convex_hull;
    const Obj o(c, body, p, kHullKeys);
    const json* pts = o.get("points");
    c.require(pts != nullptr, p, "missing key \"points\" (the hull's vertices, m, body frame)");
    s.points = read_list<Vec3>(c, *pts, o.at("points"),
                               [&](const json& e, const std::string& q) { return read_vec(c, e, q); });
    c.require(s.points.size() >= 4 && spans_volume(s.points), o.at("points"),
              "need at least 4 points not all on one plane, got " + std::to_string(s.points.size()) +
                  (s.points.size() >= 4 ? " coplanar points" : ""));
  } else {
    s.kind = ShapeKind::mesh;
    const Obj o(c, body, p, kMeshKeys);
    o.string("path", s.mesh_file);
    if (const json* vs = o.get("vertices"))
      s.vertices = read_list<Vec3>(c, *vs, o.at("vertices"),
                                   [&](const json& e, const std::string& q) { return read_vec(c, e, q); });
    if (const json* ts = o.get("triangles"))
      s.triangles = read_list<std::array<int, 3>>(
          c, *ts, o.at("triangles"),
          [&](const json& e, const std::string& q) { return read_ints<3>(c, e, q); });
    o.real("scale", s.scale);
    positive(c, s.scale, o.at("scale"));
  }
  return s;
}

// Relative tolerance on |q| = 1 for a hand-written quaternion; below 8 eps
// the quaternion is taken as already normalised (so that parsing what
// to_json wrote gives back the same numbers).
constexpr double kQuatTol = 1e-3;

RigidSpec read_body(const Ctx& c, const json& v, const std::string& path) {
  const Obj o(c, v, path, kBodyKeys);
  RigidSpec b;
  o.string("name", b.name);
  const json* shape = o.get("shape");
  c.require(shape != nullptr, path, "missing key \"shape\" (e.g. {\"sphere\": {\"radius\": 0.5}})");
  b.shape = read_shape(c, *shape, o.at("shape"));
  o.real("mass", b.mass);
  c.require(b.mass >= Real(0), o.at("mass"), "must be >= 0 (kg; 0 = static), got " + num(b.mass));
  if (b.shape.kind == ShapeKind::plane || b.shape.kind == ShapeKind::mesh)
    c.require(b.mass == Real(0), o.at("mass"),
              std::string("must be 0 for a ") + (b.shape.kind == ShapeKind::plane ? "plane" : "mesh") +
                  " shape (static only), got " + num(b.mass));
  o.vec("position", b.position);
  if (const json* q = o.get("orientation")) {
    const std::string qp = o.at("orientation");
    if (!q->is_array() || q->size() != 4)
      c.fail(qp, "expected a unit quaternion [w, x, y, z], got " + show(*q));
    double n2 = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      b.orientation[i] = read_real(c, (*q)[i], child(qp, i));
      n2 += double(b.orientation[i]) * double(b.orientation[i]);
    }
    const double n = std::sqrt(n2);
    c.require(std::abs(n - 1) <= kQuatTol, qp,
              "must be a unit quaternion [w, x, y, z] (|q| within 1e-3 of 1; [1, 0, 0, 0] = no rotation), "
              "got |q| = " +
                  num(n));
    if (std::abs(n2 - 1) > 8 * double(xpbd::kEpsilon))
      for (Real& x : b.orientation) x = static_cast<Real>(double(x) / n);
  }
  o.vec("velocity", b.velocity);
  o.vec("angular_velocity", b.angular_velocity);
  o.real("friction", b.friction);
  non_negative(c, b.friction, o.at("friction"));
  o.real("restitution", b.restitution);
  unit_interval(c, b.restitution, o.at("restitution"));
  o.real("linear_damping", b.linear_damping);
  unit_interval(c, b.linear_damping, o.at("linear_damping"));
  o.real("angular_damping", b.angular_damping);
  unit_interval(c, b.angular_damping, o.at("angular_damping"));
  o.boolean("kinematic", b.kinematic);
  return b;
}

// ---------------------------------------------------------------------------
// SceneError messages ("distances[3].mat.compliance: reason") -> JSON paths.

struct SplitError {
  std::vector<std::string> tokens;  // "distances", "3", "mat", "compliance"
  std::string dotted;               // "distances[3].mat.compliance"
  std::string reason;
};

// Splits "<dotted path>: <reason>". The dotted path is xpbd's naming:
// fields joined by '.', indices in brackets, "p0".."p3" for element
// particles, "p0..p3" for all of them, "nx/ny" for a pair of fields.
std::optional<SplitError> split_error(const std::string& msg) {
  const auto colon = msg.find(": ");
  if (colon == std::string::npos) return std::nullopt;
  SplitError e;
  e.dotted = msg.substr(0, colon);
  e.reason = msg.substr(colon + 2);
  std::string d = e.dotted;
  for (const char* range : {"p0..p3", "p1..p3"}) {
    const auto at = d.find(range);
    if (at != std::string::npos) d.replace(at, std::strlen(range), "p");
  }
  std::string cur;
  auto flush = [&] {
    if (cur.empty()) return;
    const auto slash = cur.find('/');  // "nx/ny": name the first
    if (slash != std::string::npos) cur.resize(slash);
    // "p2" -> "p", "2"
    if (cur.size() >= 2 && cur[0] == 'p' &&
        std::all_of(cur.begin() + 1, cur.end(), [](char ch) { return ch >= '0' && ch <= '9'; })) {
      e.tokens.push_back("p");
      e.tokens.push_back(cur.substr(1));
    } else {
      e.tokens.push_back(cur);
    }
    cur.clear();
  };
  for (char ch : d) {
    if (ch == '.' || ch == '[') {
      flush();
    } else if (ch == ']') {
      e.tokens.push_back(cur);
      cur.clear();
    } else if (ch == ' ') {
      return std::nullopt;  // not a dotted path (e.g. a file path with spaces)
    } else {
      cur += ch;
    }
  }
  flush();
  if (e.tokens.empty()) return std::nullopt;
  return e;
}

std::string join(const std::string& base, const std::vector<std::string>& tokens, std::size_t from) {
  std::string p = base;
  for (std::size_t i = from; i < tokens.size(); ++i)
    if (tokens[i] != "indices") p = child(p, tokens[i]);
  return p;
}

const char* generator_kind(const Generator& g) {
  switch (g.index()) {
    case 0:
      return "cloth";
    case 1:
      return "rope";
    case 2:
      return "tet_box";
    default:
      return "obj";
  }
}

// Rethrows a SceneError of expand() or compile() as a SceneFileError at the
// JSON path of the element it names.
[[noreturn]] void map_soft_error(const Ctx& c, const xpbd::SceneError& err, const SoftSpec& soft,
                                 const ExpandedSoft* ex) {
  const std::string msg = err.what();
  const auto e = split_error(msg);
  if (!e) c.fail("/soft", msg);
  const auto& t = e->tokens;
  const std::string soft_path = "/soft";
  if (t[0] == "generators" || t[0] == "self_collision" ||
      (t[0] == "particles" && t.size() > 1 && t[1] == "positions"))
    c.fail(join(soft_path, t, 0), e->reason);
  if (t[0] == "scene" && t.size() == 2) c.fail(join(soft_path + "/particles", t, 1), e->reason);
  if (!ex || ex->part_sizes.empty() || t.size() < 2) c.fail(soft_path, msg);
  std::size_t k = 0;
  try {
    k = std::stoul(t[1]);
  } catch (const std::exception&) {
    c.fail(soft_path, msg);
  }
  const std::string array = t[0] == "particles" ? "positions" : t[0];
  const auto it = ex->part_sizes[0].find(array);
  if (it == ex->part_sizes[0].end()) c.fail(soft_path, msg);
  if (k < it->second) {
    // An explicit element.
    if (t[0] == "particles") {
      static const std::map<std::string, std::string> field = {
          {"position", "positions"}, {"mass", "masses"}, {"velocity", "velocities"}, {"radius", "radii"}};
      const auto f = t.size() > 2 ? field.find(t[2]) : field.end();
      if (f != field.end()) c.fail(soft_path + "/particles/" + f->second + "/" + t[1], e->reason);
      c.fail(soft_path + "/particles", msg);
    }
    c.fail(join(soft_path, t, 0), e->reason);
  }
  // A generated element: name the generator that made it.
  for (std::size_t g = 0; g + 1 < ex->part_sizes.size(); ++g)
    if (k < ex->part_sizes[g + 1].at(array))
      c.fail(soft_path + "/generators/" + std::to_string(g) + "/" + generator_kind(soft.generators[g]),
             "generated " + e->dotted + ": " + e->reason);
  c.fail(soft_path, msg);
}

// Full validation of what needs more than one field: the expanded and
// compiled particle system, indices into it, the bodies' meshes.
void validate(const Ctx& c, const SceneSpec& s) {
  ExpandedSoft ex;
  try {
    ex = expand(s.soft, s.base_dir);
  } catch (const xpbd::SceneError& e) {
    map_soft_error(c, e, s.soft, nullptr);
  }
  try {
    (void)xpbd::compile(ex.scene);
  } catch (const xpbd::SceneError& e) {
    map_soft_error(c, e, s.soft, &ex);
  }
  const Index n = ex.scene.num_particles();
  for (std::size_t b = 0; b < s.bodies.size(); ++b) {
    if (s.bodies[b].shape.kind != ShapeKind::mesh) continue;
    const std::string base = "/bodies/" + std::to_string(b) + "/shape";
    try {
      (void)body_mesh(s.bodies[b].shape, s.base_dir);
    } catch (const xpbd::io::ObjError& e) {
      c.fail(base + "/mesh/path", e.what());
    } catch (const xpbd::SceneError& e) {
      const auto se = split_error(e.what());
      if (!se) c.fail(base, e.what());
      c.fail(join(base, se->tokens, 1), se->reason);
    }
  }
  for (std::size_t a = 0; a < s.attachments.size(); ++a) {
    const AttachmentSpec& at = s.attachments[a];
    const std::string p = "/attachments/" + std::to_string(a);
    c.require(at.particle >= 0 && at.particle < n, p + "/particle",
              "index " + std::to_string(at.particle) + " out of range [0, " + std::to_string(n) + ")");
    c.require(
        at.body >= 0 && std::size_t(at.body) < s.bodies.size(), p + "/body",
        "index " + std::to_string(at.body) + " out of range [0, " + std::to_string(s.bodies.size()) + ")");
  }
  // Last, so an error in an element is named first.
  c.require(n > 0, "/soft",
            "the scene has no particles: give soft.particles or a generator (docs/scene-format.md)");
}

// ---------------------------------------------------------------------------
// JSON text: position tracking for messages the parser cannot place.

struct Tracker {
  struct Frame {
    bool array = false;
    std::size_t count = 0;  // arrays: elements started
    std::string key;        // objects: current key
    std::set<std::string> keys;
  };
  std::vector<Frame> stack;
  std::string duplicate;  // path of the first duplicate key

  // Path of the value being parsed.
  std::string path() const {
    std::string p;
    for (std::size_t i = 0; i < stack.size(); ++i) {
      const Frame& f = stack[i];
      const bool inner = i + 1 < stack.size();  // an element of f is a container being parsed
      if (f.array)
        p = child(p, inner ? f.count - 1 : f.count);
      else if (!f.key.empty() || !f.keys.empty())
        p = child(p, f.key);
    }
    return p;
  }

  bool operator()(int, json::parse_event_t ev, json& parsed) {
    switch (ev) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        if (!stack.empty() && stack.back().array) ++stack.back().count;
        stack.push_back(Frame{ev == json::parse_event_t::array_start, 0, {}, {}});
        break;
      case json::parse_event_t::key: {
        Frame& f = stack.back();
        f.key = parsed.get<std::string>();
        if (!f.keys.insert(f.key).second && duplicate.empty()) duplicate = path();
        break;
      }
      case json::parse_event_t::value:
        if (!stack.empty() && stack.back().array) ++stack.back().count;
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        stack.pop_back();
        break;
    }
    return true;
  }
};

// ---------------------------------------------------------------------------
// Writing.

json out_generator(const Generator& g) {
  if (const auto* d = std::get_if<xpbd::ClothGridDesc>(&g)) {
    json pinned = json::array();
    for (const auto& [i, j] : d->pinned) pinned.push_back({i, j});
    return {{"cloth",
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
  }
  if (const auto* d = std::get_if<xpbd::RopeDesc>(&g)) {
    return {{"rope",
             {{"n", d->n},
              {"start", out_vec(d->start)},
              {"dir", out_vec(d->dir)},
              {"spacing", out_real(d->spacing)},
              {"mass", out_real(d->mass)},
              {"radius", out_real(d->radius)},
              {"pin_first", d->pin_first},
              {"mat", out_mat(d->mat)}}}};
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
                   {"feature_spacing", out_real(c.feature_spacing)}};
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

bool valid_name(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](char ch) {
    return (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_' || ch == '-';
  });
}

}  // namespace

// ---------------------------------------------------------------------------

SceneSpec parse_scene(const json& j, const std::string& file_label, const std::filesystem::path& base_dir) {
  const Ctx c{file_label};
  const Obj o(c, j, "", kTopKeys);
  SceneSpec s;
  s.base_dir = base_dir;
  o.string("name", s.name);
  c.require(valid_name(s.name), o.at("name"),
            "may contain only a-z, 0-9, '_' and '-', got " + show(json(s.name)));
  o.string("description", s.description);
  if (const json* v = o.get("solver")) s.solver = read_solver(c, *v, o.at("solver"));
  if (const json* v = o.get("soft")) s.soft = read_soft(c, *v, o.at("soft"));
  if (const json* v = o.get("bodies"))
    s.bodies = read_list<RigidSpec>(c, *v, o.at("bodies"),
                                    [&](const json& e, const std::string& q) { return read_body(c, e, q); });
  // Body names: optional, unique when given (attachments may use them).
  for (std::size_t a = 0; a < s.bodies.size(); ++a)
    for (std::size_t b = 0; b < a; ++b)
      if (!s.bodies[a].name.empty() && s.bodies[a].name == s.bodies[b].name)
        c.fail("/bodies/" + std::to_string(a) + "/name", "duplicate body name " +
                                                             show(json(s.bodies[a].name)) +
                                                             " (also /bodies/" + std::to_string(b) + ")");
  if (const json* v = o.get("attachments"))
    s.attachments =
        read_list<AttachmentSpec>(c, *v, o.at("attachments"), [&](const json& e, const std::string& q) {
          const Obj a(c, e, q, kAttachmentKeys);
          AttachmentSpec at;
          const json* particle = a.get("particle");
          c.require(particle != nullptr, q, "missing key \"particle\" (a particle index)");
          at.particle = read_int(c, *particle, a.at("particle"));
          const json* body = a.get("body");
          c.require(body != nullptr, q, "missing key \"body\" (a body index or name)");
          if (body->is_string()) {
            const std::string name = body->get<std::string>();
            const auto it = std::find_if(s.bodies.begin(), s.bodies.end(),
                                         [&](const RigidSpec& r) { return !name.empty() && r.name == name; });
            c.require(it != s.bodies.end(), a.at("body"), "no body is named " + show(*body));
            at.body = int(it - s.bodies.begin());
          } else {
            at.body = read_int(c, *body, a.at("body"));
          }
          if (const json* l = a.get("local")) at.local = read_vec(c, *l, a.at("local"));
          a.real("compliance", at.compliance);
          non_negative(c, at.compliance, a.at("compliance"));
          return at;
        });
  try {
    validate(c, s);
  } catch (const SceneFileError&) {
    throw;
  } catch (const std::bad_alloc&) {
    c.fail("/soft", "out of memory while building the scene");
  } catch (const std::length_error&) {
    c.fail("/soft", "out of memory while building the scene");
  } catch (const std::exception& e) {
    throw SceneFileError(file_label, "", e.what());
  }
  return s;
}

json parse_json_text(const std::string& text, const std::string& file_label) {
  if (std::all_of(text.begin(), text.end(),
                  [](char ch) { return ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r'; }))
    throw SceneFileError(file_label, "", "the file is empty; a scene is a JSON object { ... }");
  Tracker tracker;
  json j;
  try {
    j = json::parse(
        text, [&](int depth, json::parse_event_t ev, json& parsed) { return tracker(depth, ev, parsed); });
  } catch (const json::parse_error& e) {
    // "[json.exception.parse_error.101] parse error at line 3, column 7: ..."
    std::string what = e.what();
    const auto close = what.find("] ");
    if (close != std::string::npos) what = what.substr(close + 2);
    throw SceneFileError(file_label, "", "invalid JSON: " + what);
  } catch (const json::exception& e) {
    // Number overflow (1e999): the parser has no line here, but the tracker
    // knows which value it was reading.
    std::string what = e.what();
    const auto close = what.find("] ");
    if (close != std::string::npos) what = what.substr(close + 2);
    throw SceneFileError(file_label, tracker.path().empty() ? "/" : tracker.path(),
                         what + " (must be a finite number)");
  }
  if (!tracker.duplicate.empty())
    throw SceneFileError(file_label, tracker.duplicate,
                         "duplicate key (each key may appear once per object)");
  return j;
}

SceneSpec load_scene_file(const std::filesystem::path& file) {
  const std::string label = file.string();
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw SceneFileError(label, "", "cannot open: Is a directory");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw SceneFileError(label, "", std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw SceneFileError(label, "", std::string("cannot read: ") + std::strerror(errno));
  const json j = parse_json_text(buf.str(), label);
  return parse_scene(j, label, file.parent_path());
}

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
                 {"gravity", out_vec(v.gravity)},
                 {"bullet_kLST", out_real(v.bullet_kLST)},
                 {"max_strain", v.max_strain},
                 {"tolerance", v.tolerance},
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

void apply_set(json& j, const std::string& assignment) {
  const std::string label = "--set";
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneFileError(label, "",
                         "expected path=value (e.g. solver.substeps=20), got \"" + assignment + "\"");
  const std::string path = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  json* node = &j;
  std::string pointer;
  std::size_t start = 0;
  while (start <= path.size()) {
    const auto dot = path.find('.', start);
    const std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    start = dot == std::string::npos ? path.size() + 1 : dot + 1;
    if (key.empty()) throw SceneFileError(label, "", "empty field name in path \"" + path + "\"");
    if (node->is_object()) {
      pointer = child(pointer, key);
      const auto it = node->find(key);
      if (it == node->end()) {
        std::string list;
        for (const auto& item : node->items()) list += (list.empty() ? "" : ", ") + item.key();
        throw SceneFileError(label, pointer, "no such field in the scene (here: " + list + ")");
      }
      node = &*it;
    } else if (node->is_array()) {
      std::size_t i = 0;
      const auto r = std::from_chars(key.data(), key.data() + key.size(), i);
      pointer = child(pointer, key);
      if (r.ec != std::errc() || r.ptr != key.data() + key.size())
        throw SceneFileError(label, pointer, "expected an array index (0, 1, ...), got \"" + key + "\"");
      if (i >= node->size())
        throw SceneFileError(label, pointer,
                             "index " + key + " out of range [0, " + std::to_string(node->size()) + ")");
      node = &(*node)[i];
    } else {
      throw SceneFileError(label, pointer,
                           "is a " + std::string(node->type_name()) + ", it has no field \"" + key + "\"");
    }
  }
  json value;
  try {
    value = json::parse(text);
  } catch (const json::exception&) {
    value = text;  // not JSON: a string
  }
  *node = value;
}

SceneSpec apply_sets(const SceneSpec& s, const std::vector<std::string>& assignments,
                     const std::string& file_label) {
  json j = to_json(s);
  for (const std::string& a : assignments) apply_set(j, a);
  return parse_scene(j, file_label, s.base_dir);
}

std::string scene_text(const json& j) {
  std::string out;
  write_text(out, j, 0, 0);
  out += '\n';
  return out;
}

}  // namespace xpbd_demos
