#pragma once
// The scene file format's names, keys and number formatting, shared by the
// reader (scene_file.cpp) and the writer (scene_file_write.cpp). Internal to
// xpbd-demo: docs/scene-format.md is the format's description.
#include <array>
#include <charconv>
#include <cmath>
#include <initializer_list>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <nlohmann/json.hpp>

#include "demos/scene_spec.hpp"
#include "xpbd/error.hpp"

namespace xpbd_demos::scene_format {

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

inline constexpr EnumName<Solver> kSolvers[] = {
    {"xpbd", Solver::xpbd}, {"pbd", Solver::pbd}, {"bullet", Solver::bullet}};
inline constexpr EnumName<ToleranceMeasure> kToleranceMeasures[] = {{"strain", ToleranceMeasure::strain},
                                                                  {"residual", ToleranceMeasure::residual}};
inline constexpr EnumName<xpbd::HingeBending> kHinge[] = {{"none", xpbd::HingeBending::none},
                                                   {"dihedral", xpbd::HingeBending::dihedral},
                                                   {"isometric", xpbd::HingeBending::isometric}};
inline constexpr EnumName<xpbd::ClothPins> kClothPins[] = {{"none", xpbd::ClothPins::none},
                                                    {"top_corners", xpbd::ClothPins::top_corners},
                                                    {"top_edge", xpbd::ClothPins::top_edge},
                                                    {"all_corners", xpbd::ClothPins::all_corners}};
inline constexpr EnumName<xpbd::TetherAnchors> kTetherAnchors[] = {
    {"none", xpbd::TetherAnchors::none},
    {"all_pinned", xpbd::TetherAnchors::all_pinned},
    {"nearest_pinned", xpbd::TetherAnchors::nearest_pinned}};
inline constexpr EnumName<xpbd::TetherMetric> kTetherMetric[] = {{"euclidean", xpbd::TetherMetric::euclidean},
                                                          {"geodesic", xpbd::TetherMetric::geodesic}};
inline constexpr EnumName<xpbd::TetSplit> kTetSplit[] = {{"five", xpbd::TetSplit::five},
                                                  {"six", xpbd::TetSplit::six}};
inline constexpr EnumName<xpbd::MeshKind> kMeshKind[] = {{"cloth", xpbd::MeshKind::cloth},
                                                  {"closed_surface", xpbd::MeshKind::closed_surface}};

template <class E, std::size_t N>
const char* enum_name(const EnumName<E> (&table)[N], E v) {
  for (const auto& e : table)
    if (e.value == v) return e.name;
  return "?";
}

// ---------------------------------------------------------------------------
// Small helpers.

inline std::string num(double v) { return xpbd::format_value(v); }

// A JSON value as it appears in a message, shortened.
inline std::string show(const json& v) {
  std::string s = v.dump();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

// One JSON pointer token (RFC 6901: "~" -> "~0", "/" -> "~1").
inline std::string token(std::string_view key) {
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

inline std::string child(const std::string& path, std::string_view key) { return path + "/" + token(key); }
inline std::string child(const std::string& path, std::size_t i) { return path + "/" + std::to_string(i); }

// A Real as a JSON number that parses back to exactly the same Real. For a
// float, the shortest decimal that reads back as that float (0.1f is
// written 0.1, not 0.100000001490116), unless reading it as a double and
// rounding to float could land elsewhere; then the exact double value.
inline double out_real(Real v) {
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

inline json out_vec(const Vec3& v) { return json::array({out_real(v.x()), out_real(v.y()), out_real(v.z())}); }

inline json out_mat(const Material& m) {
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
inline constexpr Keys kTopKeys{"name", "description", "solver", "soft", "bodies", "attachments"};
inline constexpr Keys kSolverKeys{"method", "dt", "substeps", "iterations", "frames", "drag", "alternate_sweeps",
                           "coloured", "direct_chains", "chain_passes", "chain_tolerance", "hierarchy", "hierarchy_slack", "gravity", "bullet_kLST", "max_strain",
                           "tolerance", "tolerance_measure", "penetration_tolerance", "max_substeps"};
inline constexpr Keys kSoftKeys{"particles", "generators", "contacts", "distances", "collisions", "pins", "planes",
                     "penetrations", "dihedral_bends", "isometric_bends", "tets", "tethers",
                     "global_volumes", "self_collision", "collision_triangles"};
inline constexpr Keys kParticlesKeys{"positions", "masses", "velocities", "radii"};
inline constexpr Keys kMaterialKeys{"compliance", "damping", "stiffness"};
inline constexpr Keys kDistanceKeys{"a", "b", "rest", "mat"};
inline constexpr Keys kCollisionKeys{"a", "b", "mat"};
inline constexpr Keys kPinKeys{"particle", "target", "mat"};
inline constexpr Keys kPlaneKeys{"normal", "offset", "mat"};
inline constexpr Keys kPenetrationKeys{"p", "thickness", "mat"};
inline constexpr Keys kDihedralKeys{"p", "rest_angle", "mat"};
inline constexpr Keys kIsometricKeys{"p", "mat"};
inline constexpr Keys kTetKeys{"p", "rest_volume", "mat"};
inline constexpr Keys kTetherKeys{"particle", "anchor", "length", "mat"};
inline constexpr Keys kGlobalVolumeKeys{"triangles", "pressure", "mat"};
inline constexpr Keys kSelfCollisionKeys{"enabled", "distance", "skip_connected", "mat"};
inline constexpr Keys kClothKeys{"nx", "ny", "size_u", "size_v", "origin", "u", "v", "mass", "radius", "stretch",
                      "shear", "shear_both_diagonals", "shear_mat", "bend_distance", "bend_mat",
                      "hinge_bending", "hinge_mat", "pins", "pinned", "tethers", "tether_metric",
                      "tether_mat", "collision_triangles", "velocity", "particle_masses"};
inline constexpr Keys kClothMassKeys{"i", "j", "mass"};
inline constexpr Keys kRopeKeys{"n", "start", "dir", "spacing", "mass", "radius", "pin_first", "mat", "velocity",
                                "particle_masses"};
inline constexpr Keys kRopeMassKeys{"particle", "mass"};
inline constexpr Keys kTetBoxKeys{"nx", "ny", "nz", "origin", "size", "split", "mass", "radius", "volume_mat",
                       "bulk_modulus", "edges", "edge_mat", "pinned"};
inline constexpr Keys kObjKeys{"path", "triangulate", "kind", "scale", "offset", "mass", "radius", "edge_mat",
                    "bending", "bend_mat", "pressure", "volume_mat"};
inline constexpr Keys kContactsKeys{"thickness", "margin", "static_friction", "dynamic_friction", "restitution",
                         "compliance", "feature_spacing", "wedges", "edge_contacts", "surface_edges"};
inline constexpr Keys kBodyKeys{"name", "shape", "mass", "position", "orientation", "velocity", "angular_velocity",
                         "friction", "restitution", "linear_damping", "angular_damping", "kinematic"};
inline constexpr Keys kSphereKeys{"radius"};
inline constexpr Keys kBoxKeys{"half_extents"};
inline constexpr Keys kCapsuleKeys{"radius", "height"};
inline constexpr Keys kShapePlaneKeys{"normal", "offset"};
inline constexpr Keys kHullKeys{"points"};
inline constexpr Keys kMeshKeys{"path", "vertices", "triangles", "scale"};
inline constexpr Keys kAttachmentKeys{"particle", "body", "local", "compliance"};
// clang-format on

inline const std::vector<const Keys*>& all_key_lists() {
  static const std::vector<const Keys*> lists = {
      &kTopKeys,           &kSolverKeys,    &kSoftKeys,   &kParticlesKeys, &kMaterialKeys,
      &kDistanceKeys,      &kCollisionKeys, &kPinKeys,    &kPlaneKeys,     &kPenetrationKeys,
      &kDihedralKeys,      &kIsometricKeys, &kTetKeys,    &kTetherKeys,    &kGlobalVolumeKeys,
      &kSelfCollisionKeys, &kClothKeys,     &kRopeKeys,   &kTetBoxKeys,    &kObjKeys,
      &kContactsKeys,      &kBodyKeys,      &kSphereKeys, &kBoxKeys,       &kCapsuleKeys,
      &kShapePlaneKeys,    &kHullKeys,      &kMeshKeys,   &kAttachmentKeys, &kClothMassKeys,
      &kRopeMassKeys};
  return lists;
}

}  // namespace xpbd_demos::scene_format
