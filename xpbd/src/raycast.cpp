#include "xpbd/raycast.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "xpbd/error.hpp"

namespace xpbd {

namespace {

std::string vec(const Vec3& v) {
  return "(" + format_value(double(v.x())) + ", " + format_value(double(v.y())) + ", " +
         format_value(double(v.z())) + ")";
}

// The segment from + f d, f in [0, 1], against triangle (a, b, c)
// (Moller and Trumbore 1997). Fills f, the weights and the unit normal.
bool hit_triangle(const Vec3& from, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c, RayHit& h) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 n = e1.cross(e2);
  const Real area2 = n.norm();
  const Real dn = d.norm();
  if (!(area2 > Real(0)) || !(dn > Real(0))) return false;
  const Vec3 p = d.cross(e2);
  const Real det = e1.dot(p);  // = -d . n
  // In the triangle's plane (to round-off): never a hit.
  if (!(std::abs(det) > Real(8) * std::numeric_limits<Real>::epsilon() * dn * area2)) return false;
  const Real inv = Real(1) / det;
  const Vec3 t = from - a;
  const Real u = t.dot(p) * inv;
  if (u < Real(0) || u > Real(1)) return false;
  const Vec3 q = t.cross(e1);
  const Real v = d.dot(q) * inv;
  if (v < Real(0) || u + v > Real(1)) return false;
  const Real f = e2.dot(q) * inv;
  if (!(f >= Real(0) && f <= Real(1))) return false;
  h.fraction = f;
  h.barycentric = {Real(1) - u - v, u, v};
  h.normal = n / area2;
  if (h.normal.dot(d) > Real(0)) h.normal = -h.normal;
  return true;
}

}  // namespace

const std::vector<std::array<Index, 3>>& ray_triangles(const Model& m) {
  return m.surface_triangles.empty() ? m.collision_triangles : m.surface_triangles;
}

std::vector<RayHit> ray_hits(const Model& m, const State& s, const Vec3& from, const Vec3& to) {
  if (!from.allFinite()) throw ConfigError("ray: from must be finite, got " + vec(from));
  if (!to.allFinite()) throw ConfigError("ray: to must be finite, got " + vec(to));
  if (s.x.size() != static_cast<std::size_t>(m.num_particles()))
    throw ConfigError("ray: the state has " + std::to_string(s.x.size()) + " particles, the model " +
                      std::to_string(m.num_particles()));
  std::vector<RayHit> hits;
  const Vec3 d = to - from;
  const Vec3 lo = from.cwiseMin(to), hi = from.cwiseMax(to);
  const auto& tris = ray_triangles(m);
  for (std::size_t k = 0; k < tris.size(); ++k) {
    const auto& tri = tris[k];
    const Vec3& a = s.x[static_cast<std::size_t>(tri[0])];
    const Vec3& b = s.x[static_cast<std::size_t>(tri[1])];
    const Vec3& c = s.x[static_cast<std::size_t>(tri[2])];
    // The segment's box against the triangle's (a NaN corner fails both).
    const Vec3 tlo = a.cwiseMin(b).cwiseMin(c), thi = a.cwiseMax(b).cwiseMax(c);
    if (!((tlo.array() <= hi.array()).all() && (thi.array() >= lo.array()).all())) continue;
    if (!a.allFinite() || !b.allFinite() || !c.allFinite()) continue;
    RayHit h;
    if (!hit_triangle(from, d, a, b, c, h)) continue;
    h.triangle = k;
    h.particles = tri;
    h.point = from + h.fraction * d;
    h.distance = h.fraction * d.norm();
    hits.push_back(h);
  }
  std::sort(hits.begin(), hits.end(), [](const RayHit& x, const RayHit& y) {
    return x.fraction != y.fraction ? x.fraction < y.fraction : x.triangle < y.triangle;
  });
  return hits;
}

std::optional<RayHit> ray_closest(const Model& m, const State& s, const Vec3& from, const Vec3& to) {
  std::vector<RayHit> hits = ray_hits(m, s, from, to);
  if (hits.empty()) return std::nullopt;
  return hits.front();
}

}  // namespace xpbd
