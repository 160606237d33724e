// Reading scene files: rigid bodies and their shapes ("bodies").
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

}  // namespace

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

}  // namespace xpbd_demos::scene_read
