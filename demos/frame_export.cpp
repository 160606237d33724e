#include "demos/frame_export.hpp"

#include <LinearMath/btConvexHullComputer.h>

#include <Eigen/Geometry>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "demos/output.hpp"
#include "xpbd/error.hpp"

namespace xpbd_demos {

namespace fs = std::filesystem;
using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;
using Tri = std::array<Index, 3>;

namespace {

// Shortest decimal form that reads back to the same value (std::to_chars
// without a precision), independent of the locale.
void append_real(std::string& s, Real v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}

std::string real_str(Real v) {
  std::string s;
  append_real(s, v);
  return s;
}

void append_int(std::string& s, long long v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}

[[noreturn]] void bad_shape(const std::string& field, const std::string& rule, Real value) {
  throw xpbd::SceneError("shape." + field + ": " + rule + ", got " + real_str(value));
}

void require_positive(const std::string& field, Real v) {
  if (!(std::isfinite(v) && v > 0)) bad_shape(field, "must be > 0", v);
}

void require_finite(const std::string& field, const Vec3& v) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(v[k])) bad_shape(field + "[" + std::to_string(k) + "]", "must be finite", v[k]);
}

// A surface of revolution about the local y axis from a profile of
// (radius, y) points listed from top to bottom. A point of radius 0 is a pole
// (one vertex); the others are rings of `segments` vertices. Vertex j of a
// ring sits at angle phi_j = 2 pi j / segments, at (rho cos phi, y,
// -rho sin phi): phi grows counter-clockwise seen from +y, and with the
// orders below every triangle is counter-clockwise seen from outside (worked
// out for phi = 0: the cross product of the two edges points along +x, or +y
// at the top pole).
RigidMesh revolve(const std::vector<std::pair<Real, Real>>& profile, int segments) {
  RigidMesh m;
  const Real two_pi = Real(2) * std::numbers::pi_v<Real>;
  std::vector<Index> first;  // first vertex of each profile point
  for (const auto& [rho, y] : profile) {
    first.push_back(static_cast<Index>(m.vertices.size()));
    if (rho == 0) {
      m.vertices.emplace_back(Real(0), y, Real(0));
    } else {
      for (int j = 0; j < segments; ++j) {
        const Real phi = two_pi * Real(j) / Real(segments);
        m.vertices.emplace_back(rho * std::cos(phi), y, -rho * std::sin(phi));
      }
    }
  }
  const auto at = [&](std::size_t p, int j) -> Index {
    return profile[p].first == 0 ? first[p] : first[p] + static_cast<Index>(j % segments);
  };
  for (std::size_t p = 0; p + 1 < profile.size(); ++p) {
    const bool top_pole = profile[p].first == 0;
    const bool bottom_pole = profile[p + 1].first == 0;
    for (int j = 0; j < segments; ++j) {
      const Index a = at(p, j), b = at(p, j + 1);          // upper ring
      const Index c = at(p + 1, j), d = at(p + 1, j + 1);  // lower ring
      if (top_pole && bottom_pole) continue;
      if (top_pole) {
        m.triangles.push_back({a, c, d});
      } else if (bottom_pole) {
        m.triangles.push_back({a, c, b});
      } else {
        m.triangles.push_back({a, c, d});
        m.triangles.push_back({a, d, b});
      }
    }
  }
  return m;
}

// Reorders each triangle of a convex mesh to be counter-clockwise seen from
// outside: its normal must point away from `inside`, an interior point.
void orient_outward(RigidMesh& m, const Vec3& inside) {
  for (Tri& t : m.triangles) {
    const Vec3& a = m.vertices[static_cast<std::size_t>(t[0])];
    const Vec3& b = m.vertices[static_cast<std::size_t>(t[1])];
    const Vec3& c = m.vertices[static_cast<std::size_t>(t[2])];
    if ((b - a).cross(c - a).dot(a - inside) < 0) std::swap(t[1], t[2]);
  }
}

RigidMesh box_mesh(const Vec3& h) {
  RigidMesh m;
  // Vertex k has the sign of bit 0/1/2 of k on x/y/z.
  for (int k = 0; k < 8; ++k)
    m.vertices.emplace_back((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(),
                            (k & 4) ? h.z() : -h.z());
  // Each face: the 4 corners with bit `axis` equal to `side`, in cyclic
  // order around the face; orient_outward fixes the winding.
  for (int axis = 0; axis < 3; ++axis) {
    const int u = 1 << ((axis + 1) % 3), v = 1 << ((axis + 2) % 3);
    for (int side = 0; side < 2; ++side) {
      const Index base = side ? (1 << axis) : 0;
      const Index q[4] = {base, base + u, base + u + v, base + v};
      m.triangles.push_back({q[0], q[1], q[2]});
      m.triangles.push_back({q[0], q[2], q[3]});
    }
  }
  orient_outward(m, Vec3::Zero());
  return m;
}

// Unit normal n and offset d of a plane shape: { x : n.x = d } with n the
// normalised `normal` and d = `offset`, the plane's signed distance from the
// body origin (m), as demos/rigid_world.cpp builds the btStaticPlaneShape.
std::pair<Vec3, Real> unit_plane(const ShapeSpec& s) {
  require_finite("normal", s.normal);
  const Real len = s.normal.norm();
  if (!(len > 0)) bad_shape("normal", "must be non-zero, |normal|", len);
  if (!std::isfinite(s.offset)) bad_shape("offset", "must be finite", s.offset);
  return {s.normal / len, s.offset};
}

// The square of half side h in the plane n.x = d (n a unit vector) centred at
// the projection of `hint` onto the plane; counter-clockwise seen from the
// side n points to.
RigidMesh plane_square(const Vec3& n, Real d, const Vec3& hint, Real h) {
  const Vec3 c = hint - n * (n.dot(hint) - d);
  // Any unit vector perpendicular to n: cross n with the axis it is least
  // aligned with.
  Eigen::Index k;
  n.cwiseAbs().minCoeff(&k);
  const Vec3 u = n.cross(Vec3::Unit(k)).normalized();
  const Vec3 v = n.cross(u);  // u x v = n
  RigidMesh m;
  m.vertices = {c - h * u - h * v, c + h * u - h * v, c + h * u + h * v, c - h * u + h * v};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.unbounded = true;
  return m;
}

RigidMesh hull_mesh(const ShapeSpec& s) {
  if (s.points.empty()) throw xpbd::SceneError("shape.points: a convex hull needs at least one point");
  std::vector<double> coords;
  coords.reserve(3 * s.points.size());
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    require_finite("points[" + std::to_string(i) + "]", s.points[i]);
    for (int k = 0; k < 3; ++k) coords.push_back(double(s.points[i][k]));
  }
  btConvexHullComputer hull;
  hull.compute(coords.data(), 3 * int(sizeof(double)), int(s.points.size()), btScalar(0), btScalar(0));
  RigidMesh m;
  for (int i = 0; i < hull.vertices.size(); ++i) {
    const btVector3& p = hull.vertices[i];
    m.vertices.emplace_back(Real(p.x()), Real(p.y()), Real(p.z()));
  }
  // Each face is a planar polygon given by a cycle of edges: split it into a
  // fan from its first vertex.
  for (int f = 0; f < hull.faces.size(); ++f) {
    const btConvexHullComputer::Edge* start = &hull.edges[hull.faces[f]];
    std::vector<Index> poly;
    const btConvexHullComputer::Edge* e = start;
    do {
      poly.push_back(Index(e->getTargetVertex()));
      e = e->getNextEdgeOfFace();
    } while (e != start);
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) m.triangles.push_back({poly[0], poly[k], poly[k + 1]});
  }
  if (!m.vertices.empty()) {
    Vec3 centroid = Vec3::Zero();
    for (const Vec3& p : m.vertices) centroid += p;
    orient_outward(m, centroid / Real(m.vertices.size()));
  }
  return m;
}

RigidMesh triangle_mesh(const ShapeSpec& s, const fs::path& base_dir) {
  // The same vertices and triangles as the Bullet world's mesh shape.
  const xpbd::TriangleMesh mesh = body_mesh(s, base_dir);
  RigidMesh m;
  m.vertices = mesh.positions;
  m.triangles.assign(mesh.triangles.begin(), mesh.triangles.end());
  return m;
}

void check_options(const TessellationOptions& opt) {
  if (opt.segments < 3)
    throw xpbd::SceneError("tessellation.segments: must be >= 3, got " + std::to_string(opt.segments));
  if (opt.rings < 2)
    throw xpbd::SceneError("tessellation.rings: must be >= 2, got " + std::to_string(opt.rings));
  if (!(std::isfinite(opt.plane_half_size) && opt.plane_half_size > 0))
    throw xpbd::SceneError("tessellation.plane_half_size: must be > 0, got " +
                           real_str(opt.plane_half_size));
}

Eigen::Quaternion<Real> unit_quaternion(const std::array<Real, 4>& q) {
  const Eigen::Quaternion<Real> e(q[0], q[1], q[2], q[3]);
  const Real n = e.norm();
  if (!(std::isfinite(n) && n > 0))
    throw xpbd::SceneError("orientation: must be a non-zero finite quaternion (w, x, y, z), got (" +
                           real_str(q[0]) + ", " + real_str(q[1]) + ", " + real_str(q[2]) + ", " +
                           real_str(q[3]) + ")");
  return e.normalized();
}

}  // namespace

RigidMesh shape_mesh(const ShapeSpec& s, const fs::path& base_dir, const TessellationOptions& opt) {
  check_options(opt);
  const Real pi = std::numbers::pi_v<Real>;
  switch (s.kind) {
    case ShapeKind::sphere: {
      require_positive("radius", s.radius);
      std::vector<std::pair<Real, Real>> profile{{Real(0), s.radius}};
      for (int k = 1; k < opt.rings; ++k) {
        const Real theta = pi * Real(k) / Real(opt.rings);  // polar angle from +y
        profile.emplace_back(s.radius * std::sin(theta), s.radius * std::cos(theta));
      }
      profile.emplace_back(Real(0), -s.radius);
      return revolve(profile, opt.segments);
    }
    case ShapeKind::capsule: {
      require_positive("radius", s.radius);
      if (!(std::isfinite(s.height) && s.height >= 0)) bad_shape("height", "must be >= 0", s.height);
      const Real h2 = s.height / 2;
      const int cap = std::max(1, opt.rings / 2);  // rings per hemisphere, equator included
      std::vector<std::pair<Real, Real>> profile{{Real(0), h2 + s.radius}};
      for (int k = 1; k <= cap; ++k) {
        const Real theta = (pi / 2) * Real(k) / Real(cap);
        profile.emplace_back(s.radius * std::sin(theta), h2 + s.radius * std::cos(theta));
      }
      // The lower equator duplicates the upper one when height is 0.
      for (int k = s.height > 0 ? 0 : 1; k < cap; ++k) {
        const Real theta = (pi / 2) * Real(k) / Real(cap);
        profile.emplace_back(s.radius * std::cos(theta), -h2 - s.radius * std::sin(theta));
      }
      profile.emplace_back(Real(0), -h2 - s.radius);
      return revolve(profile, opt.segments);
    }
    case ShapeKind::cylinder: {
      require_positive("radius", s.radius);
      require_positive("height", s.height);
      const Real h2 = s.height / 2;
      return revolve({{Real(0), h2}, {s.radius, h2}, {s.radius, -h2}, {Real(0), -h2}}, opt.segments);
    }
    case ShapeKind::box: {
      for (int k = 0; k < 3; ++k)
        require_positive("half_extents[" + std::to_string(k) + "]", s.half_extents[k]);
      return box_mesh(s.half_extents);
    }
    case ShapeKind::plane: {
      const auto [n, d] = unit_plane(s);
      return plane_square(n, d, Vec3::Zero(), opt.plane_half_size);
    }
    case ShapeKind::convex_hull:
      return hull_mesh(s);
    case ShapeKind::mesh:
      return triangle_mesh(s, base_dir);
  }
  throw xpbd::SceneError("shape.kind: unknown value " + std::to_string(int(s.kind)));
}

RigidMesh transform_mesh(const RigidMesh& body, const Vec3& position, const std::array<Real, 4>& quat_wxyz) {
  const xpbd::Mat3 r = unit_quaternion(quat_wxyz).toRotationMatrix();
  RigidMesh m = body;
  for (Vec3& p : m.vertices) p = r * p + position;
  return m;
}

RigidMesh rigid_mesh(const ShapeSpec& shape, const Vec3& position, const std::array<Real, 4>& quat_wxyz,
                     const fs::path& base_dir, const TessellationOptions& opt) {
  if (shape.kind != ShapeKind::plane)
    return transform_mesh(shape_mesh(shape, base_dir, opt), position, quat_wxyz);
  check_options(opt);
  require_finite("position", position);
  // The world plane is n_w.x = d + n_w.position with n_w = R n; its point
  // nearest the world origin is c_w = n_w (d + n_w.position), which is
  // R^T (c_w - position) in the body frame.
  const auto [n, d] = unit_plane(shape);
  const Eigen::Quaternion<Real> q = unit_quaternion(quat_wxyz);
  const Vec3 n_w = q * n;
  const Vec3 c_w = n_w * (d + n_w.dot(position));
  const Vec3 c_b = q.conjugate() * (c_w - position);
  return transform_mesh(plane_square(n, d, c_b, opt.plane_half_size), position, quat_wxyz);
}

// ---------------------------------------------------------------------------
const char* extension(ExportFormat format) { return format == ExportFormat::obj ? "obj" : "vtk"; }

fs::path frame_file_path(const fs::path& out_dir, int frame, ExportFormat format) {
  if (frame < 0) throw std::invalid_argument("frame_file_path: frame must be >= 0, got " + std::to_string(frame));
  char name[64];
  std::snprintf(name, sizeof name, "frame_%05d.%s", frame, extension(format));
  return out_dir / "frames" / name;
}

namespace {

// Checks the input of a frame writer and returns which particles are in no
// triangle or line (1 = unused).
std::vector<char> check_frame(const char* who, std::span<const Vec3> x, const std::vector<Tri>& triangles,
                              const std::vector<std::array<Index, 2>>& lines,
                              const std::vector<RigidMesh>& bodies) {
  const std::string w = who;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!x[i].allFinite())
      throw std::invalid_argument(w + ": particle " + std::to_string(i) + " has a non-finite position (" +
                                  real_str(x[i].x()) + ", " + real_str(x[i].y()) + ", " +
                                  real_str(x[i].z()) + ")");
  std::vector<char> unused(x.size(), 1);
  const auto check_index = [&](const std::string& element, Index i, std::size_t count, const char* what) {
    if (i < 0 || static_cast<std::size_t>(i) >= count)
      throw std::invalid_argument(w + ": " + element + ": index " + std::to_string(i) + " out of range (" +
                                  std::to_string(count) + " " + what + ")");
  };
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (Index i : triangles[t]) {
      check_index("triangles[" + std::to_string(t) + "]", i, x.size(), "particles");
      unused[static_cast<std::size_t>(i)] = 0;
    }
  for (std::size_t l = 0; l < lines.size(); ++l)
    for (Index i : lines[l]) {
      check_index("lines[" + std::to_string(l) + "]", i, x.size(), "particles");
      unused[static_cast<std::size_t>(i)] = 0;
    }
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const std::string name = "bodies[" + std::to_string(b) + "]";
    for (std::size_t v = 0; v < bodies[b].vertices.size(); ++v)
      if (!bodies[b].vertices[v].allFinite())
        throw std::invalid_argument(w + ": " + name + ".vertices[" + std::to_string(v) + "] is not finite");
    for (std::size_t t = 0; t < bodies[b].triangles.size(); ++t)
      for (Index i : bodies[b].triangles[t])
        check_index(name + ".triangles[" + std::to_string(t) + "]", i, bodies[b].vertices.size(), "vertices");
  }
  return unused;
}

void append_point(std::string& s, const Vec3& p) {
  append_real(s, p.x());
  s += ' ';
  append_real(s, p.y());
  s += ' ';
  append_real(s, p.z());
  s += '\n';
}

// OBJ object names end at the line end; keep them to one token.
std::string object_name(const RigidMesh& m, std::size_t k) {
  std::string n = m.name.empty() ? "body_" + std::to_string(k) : m.name;
  for (char& c : n)
    if (static_cast<unsigned char>(c) <= ' ') c = '_';
  return n;
}

}  // namespace

void write_frame_obj(const fs::path& file, std::span<const Vec3> x, const std::vector<Tri>& triangles,
                     const std::vector<std::array<Index, 2>>& lines, const std::vector<RigidMesh>& bodies) {
  const std::vector<char> unused = check_frame("write_frame_obj", x, triangles, lines, bodies);
  std::string s;
  s.reserve(64 * (x.size() + triangles.size()) + 1024);
  s += "# xpbd-bullet frame: soft body (" + std::to_string(x.size()) + " particles) and " +
       std::to_string(bodies.size()) + " rigid bodies; metres, y up\n";
  s += "o soft\n";
  for (const Vec3& p : x) {
    s += "v ";
    append_point(s, p);
  }
  // OBJ numbers vertices from 1, across the whole file.
  for (const Tri& t : triangles) {
    s += 'f';
    for (Index i : t) {
      s += ' ';
      append_int(s, i + 1LL);
    }
    s += '\n';
  }
  for (const auto& l : lines) {
    s += "l ";
    append_int(s, l[0] + 1LL);
    s += ' ';
    append_int(s, l[1] + 1LL);
    s += '\n';
  }
  for (std::size_t i = 0; i < unused.size(); ++i)
    if (unused[i]) {
      s += "p ";
      append_int(s, static_cast<long long>(i) + 1);
      s += '\n';
    }
  long long base = static_cast<long long>(x.size()) + 1;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    s += "o " + object_name(bodies[b], b) + "\n";
    for (const Vec3& p : bodies[b].vertices) {
      s += "v ";
      append_point(s, p);
    }
    for (const Tri& t : bodies[b].triangles) {
      s += 'f';
      for (Index i : t) {
        s += ' ';
        append_int(s, base + i);
      }
      s += '\n';
    }
    base += static_cast<long long>(bodies[b].vertices.size());
  }
  write_text_atomically(file, s);
}

void write_frame_vtk(const fs::path& file, std::span<const Vec3> x, const std::vector<Tri>& triangles,
                     const std::vector<std::array<Index, 2>>& lines, const std::vector<RigidMesh>& bodies) {
  const std::vector<char> unused = check_frame("write_frame_vtk", x, triangles, lines, bodies);
  std::size_t points = x.size(), polygons = triangles.size();
  for (const RigidMesh& m : bodies) {
    points += m.vertices.size();
    polygons += m.triangles.size();
  }
  std::size_t verts = 0;
  for (char u : unused) verts += u ? 1 : 0;

  std::string s;
  s.reserve(64 * (points + polygons) + 1024);
  s += "# vtk DataFile Version 3.0\n";
  s += "xpbd-bullet frame: soft body (" + std::to_string(x.size()) + " particles) and " +
       std::to_string(bodies.size()) + " rigid bodies; metres, y up\n";
  s += "ASCII\nDATASET POLYDATA\n";
  s += "POINTS " + std::to_string(points) + (sizeof(Real) == sizeof(double) ? " double\n" : " float\n");
  for (const Vec3& p : x) append_point(s, p);
  for (const RigidMesh& m : bodies)
    for (const Vec3& p : m.vertices) append_point(s, p);

  // Each cell is its vertex count followed by the point indices; the header
  // gives the number of cells and the total number of integers.
  if (verts > 0) {
    s += "VERTICES " + std::to_string(verts) + " " + std::to_string(2 * verts) + "\n";
    for (std::size_t i = 0; i < unused.size(); ++i)
      if (unused[i]) {
        s += "1 ";
        append_int(s, static_cast<long long>(i));
        s += '\n';
      }
  }
  if (!lines.empty()) {
    s += "LINES " + std::to_string(lines.size()) + " " + std::to_string(3 * lines.size()) + "\n";
    for (const auto& l : lines) {
      s += "2 ";
      append_int(s, l[0]);
      s += ' ';
      append_int(s, l[1]);
      s += '\n';
    }
  }
  if (polygons > 0) {
    s += "POLYGONS " + std::to_string(polygons) + " " + std::to_string(4 * polygons) + "\n";
    const auto append_tri = [&](const Tri& t, long long base) {
      s += '3';
      for (Index i : t) {
        s += ' ';
        append_int(s, base + i);
      }
      s += '\n';
    };
    for (const Tri& t : triangles) append_tri(t, 0);
    long long base = static_cast<long long>(x.size());
    for (const RigidMesh& m : bodies) {
      for (const Tri& t : m.triangles) append_tri(t, base);
      base += static_cast<long long>(m.vertices.size());
    }
  }
  // Cell data follows VTK's cell order: vertices, lines, polygons.
  const std::size_t cells = verts + lines.size() + polygons;
  if (cells > 0) {
    s += "CELL_DATA " + std::to_string(cells) + "\nSCALARS body int 1\nLOOKUP_TABLE default\n";
    for (std::size_t i = 0; i < verts + lines.size() + triangles.size(); ++i) s += "0\n";
    for (std::size_t b = 0; b < bodies.size(); ++b)
      for (std::size_t t = 0; t < bodies[b].triangles.size(); ++t) {
        append_int(s, static_cast<long long>(b) + 1);
        s += '\n';
      }
  }
  write_text_atomically(file, s);
}

void write_frame(ExportFormat format, const fs::path& file, std::span<const Vec3> x,
                 const std::vector<Tri>& triangles, const std::vector<std::array<Index, 2>>& lines,
                 const std::vector<RigidMesh>& bodies) {
  if (format == ExportFormat::obj)
    write_frame_obj(file, x, triangles, lines, bodies);
  else
    write_frame_vtk(file, x, triangles, lines, bodies);
}

}  // namespace xpbd_demos
