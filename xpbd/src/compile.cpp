#include "xpbd/compile.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "xpbd/error.hpp"
#include "xpbd/special_constraints.hpp"
#include "xpbd/state.hpp"
#include "stream.hpp"

namespace xpbd {
namespace {

std::string num(double v) { return xpbd::format_value(v); }

std::string vec(const Vec3& v) { return xpbd::format_vec(v); }

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

// Indices of a fixed-arity element: each in range, all distinct. Fields are
// named p0, p1, ... after the element's std::array<Index, N> p.
// "p<i>", appended rather than "p" + std::string&& (GCC -Wrestrict false positive).
std::string pfield(std::size_t i) {
  std::string f("p");
  f += std::to_string(i);
  return f;
}

template <std::size_t N>
void check_particles(const std::string& where, const std::array<Index, N>& p, Index n) {
  for (std::size_t i = 0; i < N; ++i) check_index(where, pfield(i).c_str(), p[i], n);
  for (std::size_t j = 1; j < N; ++j)
    for (std::size_t i = 0; i < j; ++i)
      if (p[i] == p[j])
        fail(where, pfield(j),
             "duplicate particle " + std::to_string(p[j]) + " (same as " + pfield(i) + ")");
}

void compile_penetrations(const SceneDesc& s, Model& m) {
  const Index n = s.num_particles();
  auto& out = m.get<Penetration>();
  out.reserve(s.penetrations.size());
  for (std::size_t k = 0; k < s.penetrations.size(); ++k) {
    const auto& d = s.penetrations[k];
    const std::string w = at("penetrations", k);
    check_particles(w, d.p, n);
    check_material(w, d.mat);
    const Real t = d.thickness ? *d.thickness : m.radius[d.p[0]];
    if (!std::isfinite(t) || !(t >= Real(0)))
      fail(w, "thickness", "must be finite and >= 0, got " + num(t));
    const Vec3 e1 = s.positions[d.p[2]] - s.positions[d.p[1]];
    const Vec3 e2 = s.positions[d.p[3]] - s.positions[d.p[1]];
    if (!(e1.cross(e2).norm() > kDegenerateRel * e1.norm() * e2.norm()))
      fail(w, "p1..p3", "triangle (" + std::to_string(d.p[1]) + ", " + std::to_string(d.p[2]) +
                            ", " + std::to_string(d.p[3]) +
                            ") has zero area in the initial positions, so its normal is undefined");
    out.push_back(Penetration{d.p, t, d.mat});
  }
}

void compile_bending(const SceneDesc& s, Model& m) {
  const Index n = s.num_particles();
  constexpr Real pi = std::numbers::pi_v<Real>;
  auto& dih = m.get<DihedralBending>();
  dih.reserve(s.dihedral_bends.size());
  for (std::size_t k = 0; k < s.dihedral_bends.size(); ++k) {
    const auto& d = s.dihedral_bends[k];
    const std::string w = at("dihedral_bends", k);
    check_particles(w, d.p, n);
    check_material(w, d.mat);
    Real phi = 0;
    if (!DihedralBending::angle(d.p, s.positions.data(), phi))
      fail(w, "p0..p3", "hinge is degenerate in the initial positions (zero-length edge p0-p1 or a "
                        "zero-area triangle), so its angle is undefined");
    const Real rest = d.rest_angle ? *d.rest_angle : phi;
    if (!std::isfinite(rest) || !(rest >= -pi && rest <= pi))
      fail(w, "rest_angle", "must be finite and in [-pi, pi] rad, got " + num(rest));
    dih.push_back(DihedralBending{d.p, rest, d.mat});
  }

  auto& iso = m.get<IsometricBending>();
  iso.reserve(s.isometric_bends.size());
  for (std::size_t k = 0; k < s.isometric_bends.size(); ++k) {
    const auto& d = s.isometric_bends[k];
    const std::string w = at("isometric_bends", k);
    check_particles(w, d.p, n);
    check_material(w, d.mat);
    const Vec3* x = s.positions.data();
    std::array<Real, 4> kw{};
    if (!IsometricBending::rest_weights(x[d.p[0]], x[d.p[1]], x[d.p[2]], x[d.p[3]], kw))
      fail(w, "p0..p3", "a rest triangle is degenerate (zero area or zero-length edge) in the "
                        "initial positions, so its cotangent weights are undefined");
    iso.push_back(IsometricBending{d.p, kw, d.mat});
  }
}

void compile_tets(const SceneDesc& s, Model& m) {
  const Index n = s.num_particles();
  auto& out = m.get<TetVolume>();
  out.reserve(s.tets.size());
  for (std::size_t k = 0; k < s.tets.size(); ++k) {
    const auto& d = s.tets[k];
    const std::string w = at("tets", k);
    check_particles(w, d.p, n);
    check_material(w, d.mat);
    Real rest;
    if (d.rest_volume) {
      rest = *d.rest_volume;
      if (!std::isfinite(rest) || rest == Real(0))
        fail(w, "rest_volume", "must be finite and != 0, got " + num(rest));
    } else {
      const Vec3* x = s.positions.data();
      rest = TetVolume::volume(x[d.p[0]], x[d.p[1]], x[d.p[2]], x[d.p[3]]);
      Real edge = 0;  // longest edge, m
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) edge = std::max(edge, (x[d.p[i]] - x[d.p[j]]).norm());
      if (!(std::abs(rest) > kDegenerateRel * edge * edge * edge))
        fail(w, "rest_volume", "the initial tetrahedron is flat (volume " + num(rest) +
                                   " m^3), so the rest volume would be 0");
    }
    out.push_back(TetVolume{d.p, rest, d.mat});
  }
}

void compile_tethers(const SceneDesc& s, Model& m) {
  const Index n = s.num_particles();
  auto& out = m.get<Tether>();
  out.reserve(s.tethers.size());
  for (std::size_t k = 0; k < s.tethers.size(); ++k) {
    const auto& d = s.tethers[k];
    const std::string w = at("tethers", k);
    check_index(w, "particle", d.particle, n);
    check_index(w, "anchor", d.anchor, n);
    if (d.particle == d.anchor)
      fail(w, "anchor", "duplicate particle " + std::to_string(d.anchor) + " (same as particle)");
    check_material(w, d.mat);
    Real len;
    if (d.length) {
      len = *d.length;
      if (!std::isfinite(len) || !(len > Real(0)))
        fail(w, "length", "must be finite and > 0, got " + num(len));
    } else {
      len = (s.positions[d.particle] - s.positions[d.anchor]).norm();
      if (!(len > Real(0)))
        fail(w, "length", "particle " + std::to_string(d.particle) + " and anchor " +
                              std::to_string(d.anchor) + " coincide, so the length would be 0");
    }
    out.push_back(Tether{{d.particle, d.anchor}, len, d.mat});
  }
}

void compile_global_volumes(const SceneDesc& s, Model& m) {
  const Index n = s.num_particles();
  auto& out = m.get<GlobalVolume>();
  out.reserve(s.global_volumes.size());
  for (std::size_t b = 0; b < s.global_volumes.size(); ++b) {
    const auto& d = s.global_volumes[b];
    const std::string w = at("global_volumes", b);
    if (d.triangles.empty()) fail(w, "triangles", "is empty");
    if (!std::isfinite(d.pressure) || !(d.pressure > Real(0)))
      fail(w, "pressure", "must be finite and > 0, got " + num(d.pressure));
    check_material(w, d.mat);
    auto tri_field = [](std::size_t t, std::size_t c) {
      return "triangles[" + std::to_string(t) + "][" + std::to_string(c) + "]";
    };
    for (std::size_t t = 0; t < d.triangles.size(); ++t) {
      const auto& tri = d.triangles[t];
      for (std::size_t c = 0; c < 3; ++c) check_index(w, tri_field(t, c).c_str(), tri[c], n);
      for (std::size_t c = 1; c < 3; ++c)
        for (std::size_t c0 = 0; c0 < c; ++c0)
          if (tri[c] == tri[c0])
            fail(w, tri_field(t, c), "duplicate particle " + std::to_string(tri[c]) +
                                         " (same as [" + std::to_string(c0) + "])");
    }
    // Closed and consistently oriented: each directed edge exactly once, and
    // its reverse exactly once.
    struct HalfEdge {
      Index a, b;
      std::size_t tri;
      bool operator<(const HalfEdge& o) const { return a != o.a ? a < o.a : b < o.b; }
    };
    std::vector<HalfEdge> he;
    he.reserve(3 * d.triangles.size());
    for (std::size_t t = 0; t < d.triangles.size(); ++t)
      for (int c = 0; c < 3; ++c) he.push_back({d.triangles[t][c], d.triangles[t][(c + 1) % 3], t});
    std::sort(he.begin(), he.end());
    auto edge_name = [](Index a, Index b) {
      return "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")";
    };
    // Duplicates first: a flipped triangle shows up as both a duplicate and a
    // missing opposite edge, and the duplicate is the clearer message.
    for (std::size_t i = 1; i < he.size(); ++i)
      if (he[i].a == he[i - 1].a && he[i].b == he[i - 1].b)
        fail(w, "triangles[" + std::to_string(he[i].tri) + "]",
             edge_name(he[i].a, he[i].b) + " has the same direction in triangles " +
                 std::to_string(he[i - 1].tri) + " and " + std::to_string(he[i].tri) +
                 ": the surface is not consistently oriented (or not manifold)");
    for (std::size_t i = 0; i < he.size(); ++i) {
      if (!std::binary_search(he.begin(), he.end(), HalfEdge{he[i].b, he[i].a, 0}))
        fail(w, "triangles[" + std::to_string(he[i].tri) + "]",
             edge_name(he[i].a, he[i].b) + " has no opposite " + edge_name(he[i].b, he[i].a) +
                 ": the surface is not closed");
    }
    // Distinct vertices (sorted), and triangles re-indexed into them.
    std::vector<Index> verts;
    verts.reserve(3 * d.triangles.size());
    for (const auto& tri : d.triangles) verts.insert(verts.end(), tri.begin(), tri.end());
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    GlobalVolume g;
    g.vert_begin = static_cast<Index>(m.global_volume_verts.size());
    g.tri_begin = static_cast<Index>(m.global_volume_tris.size());
    for (const auto& tri : d.triangles) {
      std::array<Index, 3> local{};
      for (int c = 0; c < 3; ++c)
        local[c] = g.vert_begin + static_cast<Index>(
                                      std::lower_bound(verts.begin(), verts.end(), tri[c]) -
                                      verts.begin());
      m.global_volume_tris.push_back(local);
    }
    m.global_volume_verts.insert(m.global_volume_verts.end(), verts.begin(), verts.end());
    g.vert_end = static_cast<Index>(m.global_volume_verts.size());
    g.tri_end = static_cast<Index>(m.global_volume_tris.size());
    g.mat = d.mat;
    const Real v0 = global_volume(m, g, s.positions.data(), nullptr);
    if (!(v0 > Real(0)))
      fail(w, "triangles", "enclose a volume of " + num(v0) +
                               " m^3 in the initial positions; it must be > 0 (triangles "
                               "counter-clockwise seen from outside)");
    g.rest_volume = v0;
    g.target = d.pressure * v0;
    out.push_back(g);
  }
}

// Whether particle p counts as shared between elements: always, or with
// inverse masses, only if it can move (no kernel writes a particle of
// inverse mass 0).
bool shared(const std::vector<Real>* inv_mass, Index p) {
  return inv_mass == nullptr || (*inv_mass)[static_cast<std::size_t>(p)] != Real(0);
}

// The schedule of elements whose colour (or level) is group[k], of `groups`
// groups: the groups one after another, each in array order (a stable
// counting sort).
ColourSchedule lay_out(const std::vector<Index>& group, Index groups) {
  ColourSchedule out;
  out.begin.assign(static_cast<std::size_t>(groups) + 1, 0);
  for (Index g : group) ++out.begin[static_cast<std::size_t>(g) + 1];
  for (Index g = 0; g < groups; ++g)
    out.begin[static_cast<std::size_t>(g) + 1] += out.begin[static_cast<std::size_t>(g)];
  std::vector<Index> next(out.begin.begin(), out.begin.end() - 1);
  out.order.resize(group.size());
  for (std::size_t k = 0; k < group.size(); ++k)
    out.order[static_cast<std::size_t>(next[static_cast<std::size_t>(group[k])]++)] = static_cast<Index>(k);
  return out;
}

// Greedy colouring of elements in array order (Model::ColourSchedule):
// element k takes the smallest colour that no earlier element sharing one
// of its particles has; then lay_out. Cost: O(sum over elements of the
// degrees of their particles). With `inv_mass`, particles whose inverse
// mass is 0 do not count as shared (Model::tether_colours).
template <class T>
ColourSchedule colour_elements(const std::vector<T>& cs, Index num_particles,
                               const std::vector<Real>* inv_mass = nullptr) {
  if (cs.empty()) return ColourSchedule{};
  // used[i]: the colours of the elements seen so far that touch particle i.
  std::vector<std::vector<Index>> used(static_cast<std::size_t>(num_particles));
  std::vector<Index> colour(cs.size());
  std::vector<char> taken;  // scratch, indexed by colour, all 0 between elements
  Index ncol = 0;
  for (std::size_t k = 0; k < cs.size(); ++k) {
    taken.resize(static_cast<std::size_t>(ncol) + 1, 0);
    for (Index p : cs[k].p)
      for (Index c : used[static_cast<std::size_t>(p)]) taken[static_cast<std::size_t>(c)] = 1;
    Index c = 0;
    while (taken[static_cast<std::size_t>(c)]) ++c;  // taken[ncol] is 0: stops at ncol at most
    for (Index p : cs[k].p)
      for (Index u : used[static_cast<std::size_t>(p)]) taken[static_cast<std::size_t>(u)] = 0;
    colour[k] = c;
    for (Index p : cs[k].p)
      if (shared(inv_mass, p)) used[static_cast<std::size_t>(p)].push_back(c);
    ncol = std::max(ncol, c + 1);
  }
  return lay_out(colour, ncol);
}

// Array order's levels (Model::distance_levels): element k's level is one
// more than the highest level of the earlier elements sharing one of its
// particles; then lay_out. With `inv_mass`, particles whose inverse mass is
// 0 do not count as shared (Model::tether_levels). Cost: O(elements +
// particles).
template <class T>
ColourSchedule level_elements(const std::vector<T>& cs, Index num_particles,
                              const std::vector<Real>* inv_mass = nullptr) {
  if (cs.empty()) return ColourSchedule{};
  // last[i]: the level of the last element seen so far that touches particle i.
  std::vector<Index> last(static_cast<std::size_t>(num_particles), -1);
  std::vector<Index> level(cs.size());
  Index levels = 0;
  for (std::size_t k = 0; k < cs.size(); ++k) {
    Index l = 0;
    for (Index p : cs[k].p)
      if (shared(inv_mass, p)) l = std::max(l, last[static_cast<std::size_t>(p)] + 1);
    for (Index p : cs[k].p)
      if (shared(inv_mass, p)) last[static_cast<std::size_t>(p)] = l;
    level[k] = l;
    levels = std::max(levels, l + 1);
  }
  return lay_out(level, levels);
}

}  // namespace

Index SceneDesc::add_particle(const Vec3& x, Real mass, Real radius, const Vec3& v) {
  const std::size_t n = positions.size();
  positions.push_back(x);
  masses.push_back(mass);
  // The first non-default value fills the earlier entries with defaults; it
  // must itself be kept even when it belongs to particle 0 (assign(0) leaves
  // the array empty).
  if (!v.isZero() || !velocities.empty()) {
    if (velocities.empty()) velocities.assign(n, Vec3::Zero());
    velocities.push_back(v);
  }
  if (radius != Real(0) || !radii.empty()) {
    if (radii.empty()) radii.assign(n, Real(0));
    radii.push_back(radius);
  }
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

  // Collision triangles (rigid features against the soft surface) and the
  // visible surface (rendering, ray queries).
  for (const char* field : {"collision_triangles", "surface_triangles"}) {
    const auto& tris = std::string(field) == "collision_triangles" ? s.collision_triangles : s.surface_triangles;
    for (std::size_t k = 0; k < tris.size(); ++k) {
      const auto& t = tris[k];
      const std::string w = at(field, k);
      static const char* names[3] = {"0", "1", "2"};
      for (int i = 0; i < 3; ++i) check_index(w, names[i], t[i], n);
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
        fail(w, "indices", "duplicate particle in (" + std::to_string(t[0]) + ", " +
                                std::to_string(t[1]) + ", " + std::to_string(t[2]) + ")");
    }
  }
  m.collision_triangles = s.collision_triangles;
  m.surface_triangles = s.surface_triangles;

  compile_penetrations(s, m);
  compile_bending(s, m);
  compile_tets(s, m);
  compile_tethers(s, m);
  compile_global_volumes(s, m);

  // Opt-in particle-particle collision: checked here, built from the
  // constraint arrays above (exclusions) by spatial_hash.cpp.
  if (s.self_collision.enabled) {
    const Real d = s.self_collision.distance;
    if (!std::isfinite(d) || !(d > Real(0)))
      fail("self_collision", "distance", "must be finite and > 0, got " + num(d));
    check_material("self_collision", s.self_collision.mat);
  }
  compile_self_collision(s, m);

  for_each_constraint_type([&]<class T>(std::type_identity<T>) {
    bool any = false;
    for (const T& c : m.get<T>()) any = any || c.mat.damping != Real(0);
    m.has_damping[type_index_v<T>] = any;
  });
  m.distance_colours = colour_elements(m.get<Distance>(), n);
  m.distance_by_colour.reserve(m.distance_colours.order.size());
  for (Index k : m.distance_colours.order)
    m.distance_by_colour.push_back(m.get<Distance>()[static_cast<std::size_t>(k)]);
  m.distance_stream = detail::make_distance_stream(m);
  m.distance_levels = level_elements(m.get<Distance>(), n);
  m.distance_level_stream = detail::make_distance_level_stream(m);
  m.dihedral_colours = colour_elements(m.get<DihedralBending>(), n);
  m.dihedral_stream = detail::make_dihedral_stream(m);
  m.tether_colours = colour_elements(m.get<Tether>(), n, &m.inv_mass);
  m.tether_stream = detail::make_tether_stream(m);
  m.tether_levels = level_elements(m.get<Tether>(), n, &m.inv_mass);
  m.tether_level_stream = detail::make_tether_level_stream(m);
  m.chains = find_chains(m.get<Distance>(), n);
  {
    std::vector<Index> slot(m.get<Distance>().size(), 0);
    for (std::size_t j = 0; j < m.distance_colours.order.size(); ++j)
      slot[static_cast<std::size_t>(m.distance_colours.order[j])] = static_cast<Index>(j);
    for (Index k : m.chains.element) m.chains.stream_slot.push_back(slot[static_cast<std::size_t>(k)]);
    m.trees = find_trees(m.get<Distance>(), m.inv_mass);
    for (std::size_t j = 0; j < m.trees.index.size(); ++j)
      m.trees.stream_slot.push_back(m.trees.element[j] ? slot[static_cast<std::size_t>(m.trees.index[j])] : -1);
  }
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
  s.penetration_side.assign(m.get<Penetration>().size(), Real(1));
  s.volume_grad.assign(m.global_volume_verts.size(), Vec3::Zero());
  record_penetration_sides(m, s);
  init_self_collision(m, s);
  return s;
}

}  // namespace xpbd
