#include "xpbd/builders.hpp"

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <sstream>
#include <string>

#include "edge_paths.hpp"
#include "xpbd/error.hpp"

namespace xpbd {
namespace {

std::string num(Real v) {
  std::ostringstream o;
  o.precision(9);
  o << v;
  return o.str();
}

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw SceneError(where + ": " + what);
}

void check_positive(const std::string& where, Real v) {
  if (!std::isfinite(v) || !(v > Real(0))) fail(where, "must be finite and > 0, got " + num(v));
}

void check_non_negative(const std::string& where, Real v) {
  if (!std::isfinite(v) || !(v >= Real(0))) fail(where, "must be finite and >= 0, got " + num(v));
}

// "(a, b)" with vertex numbers shifted by `base`.
std::string edge_name(Index a, Index b, int base) {
  std::ostringstream o;
  o << '(' << a + base << ", " << b + base << ')';
  return o.str();
}

// Undirected edge key, smaller index first.
std::array<Index, 2> edge_key(Index a, Index b) { return {std::min(a, b), std::max(a, b)}; }

// Distinct undirected edges of a triangle list, sorted.
std::vector<std::array<Index, 2>> triangle_edges(const std::vector<Triangle>& tris) {
  std::vector<std::array<Index, 2>> e;
  e.reserve(3 * tris.size());
  for (const Triangle& t : tris)
    for (int c = 0; c < 3; ++c) e.push_back(edge_key(t[c], t[(c + 1) % 3]));
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  return e;
}

void add_hinges(SceneDesc& s, const std::vector<std::array<Index, 4>>& hinges, HingeBending mode,
                const Material& mat) {
  if (mode == HingeBending::dihedral) {
    s.dihedral_bends.reserve(s.dihedral_bends.size() + hinges.size());
    for (const auto& h : hinges) s.dihedral_bends.push_back(DihedralBendingDesc{h, std::nullopt, mat});
  } else if (mode == HingeBending::isometric) {
    s.isometric_bends.reserve(s.isometric_bends.size() + hinges.size());
    for (const auto& h : hinges) s.isometric_bends.push_back(IsometricBendingDesc{h, mat});
  }
}

// Half-edge of a triangle: directed edge (a, b) of triangle `tri`, `wing`
// its third vertex; sorted by the undirected key.
struct HalfEdge {
  std::array<Index, 2> key;
  Index a, b, wing;
  std::size_t tri;
};

std::vector<HalfEdge> sorted_half_edges(const std::vector<Triangle>& tris) {
  std::vector<HalfEdge> he;
  he.reserve(3 * tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const Index a = tris[t][c], b = tris[t][(c + 1) % 3], w = tris[t][(c + 2) % 3];
      he.push_back(HalfEdge{edge_key(a, b), a, b, w, t});
    }
  // Stable: within an edge, triangles stay in list order, so "the first
  // triangle that has it" is well defined.
  std::stable_sort(he.begin(), he.end(),
                   [](const HalfEdge& x, const HalfEdge& y) { return x.key < y.key; });
  return he;
}

}  // namespace

// ---------------------------------------------------------------------------
// Shared helpers

std::vector<std::array<Index, 4>> mesh_hinges(const std::vector<Triangle>& tris,
                                              const std::string& name, int base) {
  const std::vector<HalfEdge> he = sorted_half_edges(tris);
  std::vector<std::array<Index, 4>> out;
  for (std::size_t i = 0; i < he.size();) {
    std::size_t j = i + 1;
    while (j < he.size() && he[j].key == he[i].key) ++j;
    if (j - i > 2) {
      std::string tri_list;
      for (std::size_t k = i; k < j; ++k)
        tri_list += (k > i ? ", " : "") + std::to_string(he[k].tri + std::size_t(base));
      fail(name, "edge " + edge_name(he[i].key[0], he[i].key[1], base) + " is shared by " +
                     std::to_string(j - i) + " triangles (" + tri_list +
                     "); a surface edge may belong to at most 2 (non-manifold mesh)");
    }
    if (j - i == 2) out.push_back({he[i].a, he[i].b, he[i].wing, he[i + 1].wing});
    i = j;
  }
  return out;
}

// ---------------------------------------------------------------------------
// Cloth grid

ClothGridDesc& ClothGridDesc::set_bending(ClothBending b, const Material& m) {
  bend_distance = b == ClothBending::distance;
  hinge_bending = b == ClothBending::dihedral    ? HingeBending::dihedral
                  : b == ClothBending::isometric ? HingeBending::isometric
                                                 : HingeBending::none;
  if (b == ClothBending::distance) bend_mat = m;
  if (hinge_bending != HingeBending::none) hinge_mat = m;
  return *this;
}

ClothGrid add_cloth_grid(SceneDesc& s, const ClothGridDesc& d) {
  if (d.nx < 2 || d.ny < 2)
    throw SceneError("cloth.nx/ny: need at least 2 x 2 particles, got " + std::to_string(d.nx) +
                     " x " + std::to_string(d.ny));
  check_positive("cloth.size_u", d.size_u);
  check_positive("cloth.size_v", d.size_v);
  check_non_negative("cloth.mass", d.mass);
  ClothGrid g;
  g.first = s.num_particles();
  g.nx = d.nx;
  g.ny = d.ny;

  // Pinned set: preset + explicit list.
  std::vector<char> pin(std::size_t(d.nx) * std::size_t(d.ny), 0);
  auto flag = [&](int i, int j) { pin[std::size_t(j) * std::size_t(d.nx) + std::size_t(i)] = 1; };
  switch (d.pins) {
    case ClothPins::none:
      break;
    case ClothPins::top_corners:
      flag(0, 0);
      flag(d.nx - 1, 0);
      break;
    case ClothPins::top_edge:
      for (int i = 0; i < d.nx; ++i) flag(i, 0);
      break;
    case ClothPins::all_corners:
      flag(0, 0);
      flag(d.nx - 1, 0);
      flag(0, d.ny - 1);
      flag(d.nx - 1, d.ny - 1);
      break;
  }
  for (const auto& [i, j] : d.pinned) {
    if (i < 0 || i >= d.nx || j < 0 || j >= d.ny)
      throw SceneError("cloth.pinned: (" + std::to_string(i) + ", " + std::to_string(j) +
                       ") is outside the " + std::to_string(d.nx) + " x " + std::to_string(d.ny) +
                       " grid");
    flag(i, j);
  }
  auto is_pinned = [&](int i, int j) {
    return pin[std::size_t(j) * std::size_t(d.nx) + std::size_t(i)] != 0;
  };
  const auto movable = std::count(pin.begin(), pin.end(), char(0));
  const Real m = movable > 0 ? d.mass / Real(movable) : Real(0);
  std::vector<Real> mass(pin.size(), m);
  for (std::size_t k = 0; k < d.particle_masses.size(); ++k) {
    const ParticleMass& pm = d.particle_masses[k];
    const std::string at = "cloth.particle_masses[" + std::to_string(k) + "]: ";
    if (pm.i < 0 || pm.i >= d.nx || pm.j < 0 || pm.j >= d.ny)
      throw SceneError(at + "(" + std::to_string(pm.i) + ", " + std::to_string(pm.j) + ") is outside the " +
                       std::to_string(d.nx) + " x " + std::to_string(d.ny) + " grid");
    if (!(pm.mass > Real(0)) || !std::isfinite(pm.mass))
      throw SceneError(at + "mass must be finite and > 0, got " + format_value(double(pm.mass)));
    if (is_pinned(pm.i, pm.j))
      throw SceneError(at + "(" + std::to_string(pm.i) + ", " + std::to_string(pm.j) +
                       ") is pinned (mass 0); a pinned particle has no mass to set");
    mass[std::size_t(pm.j) * std::size_t(d.nx) + std::size_t(pm.i)] = pm.mass;
  }
  if (!d.velocity.allFinite()) throw SceneError("cloth.velocity: must be finite, got " + format_vec(d.velocity));

  // Particles.
  const Real du = d.size_u / Real(d.nx - 1), dv = d.size_v / Real(d.ny - 1);
  for (int j = 0; j < d.ny; ++j)
    for (int i = 0; i < d.nx; ++i) {
      const bool p = is_pinned(i, j);
      const Index k = s.add_particle(d.origin + (Real(i) * du) * d.u + (Real(j) * dv) * d.v,
                                     p ? Real(0) : mass[std::size_t(j) * std::size_t(d.nx) + std::size_t(i)],
                                     d.radius, p ? Vec3(Vec3::Zero()) : d.velocity);
      if (p) {
        s.pins.push_back(PinDesc{k, std::nullopt, Material{}});
        g.pinned.push_back(k);
      }
    }

  // Distance edges.
  auto edge = [&](int i0, int j0, int i1, int j1, const Material& mat) {
    s.distances.push_back(DistanceDesc{g.at(i0, j0), g.at(i1, j1), std::nullopt, mat});
  };
  for (int j = 0; j < d.ny; ++j)
    for (int i = 0; i < d.nx; ++i) {
      if (i + 1 < d.nx) edge(i, j, i + 1, j, d.stretch);
      if (j + 1 < d.ny) edge(i, j, i, j + 1, d.stretch);
    }
  if (d.shear)
    for (int j = 0; j + 1 < d.ny; ++j)
      for (int i = 0; i + 1 < d.nx; ++i) {
        edge(i, j, i + 1, j + 1, d.shear_mat);  // the triangulation's diagonal
        if (d.shear_both_diagonals) edge(i + 1, j, i, j + 1, d.shear_mat);
      }
  if (d.bend_distance)
    for (int j = 0; j < d.ny; ++j)
      for (int i = 0; i < d.nx; ++i) {
        if (i + 2 < d.nx) edge(i, j, i + 2, j, d.bend_mat);
        if (j + 2 < d.ny) edge(i, j, i, j + 2, d.bend_mat);
      }

  // Triangulation (always returned; hinges only if asked for).
  g.triangles.reserve(2 * std::size_t(d.nx - 1) * std::size_t(d.ny - 1));
  for (int j = 0; j + 1 < d.ny; ++j)
    for (int i = 0; i + 1 < d.nx; ++i) {
      g.triangles.push_back({g.at(i, j), g.at(i + 1, j), g.at(i + 1, j + 1)});
      g.triangles.push_back({g.at(i, j), g.at(i + 1, j + 1), g.at(i, j + 1)});
    }
  if (d.hinge_bending != HingeBending::none)
    add_hinges(s, mesh_hinges(g.triangles, "cloth"), d.hinge_bending, d.hinge_mat);

  // Tethers.
  if (d.tethers != TetherAnchors::none) {
    if (g.pinned.empty())
      throw SceneError("cloth.tethers: need at least one pinned particle to anchor to, got none");
    // Lengths from one anchor at a time, so memory stays O(particles) for
    // nearest_pinned and O(tethers) for all_pinned, however many pins.
    const std::size_t n = std::size_t(d.nx) * std::size_t(d.ny);
    const std::size_t pins = g.pinned.size();
    const std::vector<std::array<Index, 2>> tri_edges =
        d.tether_metric == TetherMetric::geodesic ? triangle_edges(g.triangles)
                                                  : std::vector<std::array<Index, 2>>{};
    std::vector<Real> from_anchor(n);
    auto lengths_from = [&](std::size_t a) {
      if (d.tether_metric == TetherMetric::geodesic) {
        const std::vector<Real> all = edge_path_distances(s.positions, tri_edges, g.pinned[a]);
        std::copy(all.begin() + g.first, all.begin() + g.first + Index(n), from_anchor.begin());
      } else {
        for (std::size_t v = 0; v < n; ++v)
          from_anchor[v] = (s.positions[g.first + v] - s.positions[std::size_t(g.pinned[a])]).norm();
      }
    };
    // movable[k]: local index of the k-th movable particle.
    std::vector<std::size_t> movable;
    for (std::size_t v = 0; v < n; ++v)
      if (!pin[v]) movable.push_back(v);
    if (d.tethers == TetherAnchors::all_pinned) {
      // length[k * pins + a], in the order the tethers are appended:
      // particle by particle, anchors in order.
      std::vector<Real> length(movable.size() * pins);
      for (std::size_t a = 0; a < pins; ++a) {
        lengths_from(a);
        for (std::size_t k = 0; k < movable.size(); ++k) length[k * pins + a] = from_anchor[movable[k]];
      }
      for (std::size_t k = 0; k < movable.size(); ++k)
        for (std::size_t a = 0; a < pins; ++a)
          s.tethers.push_back(TetherDesc{g.first + Index(movable[k]), g.pinned[a], length[k * pins + a], d.tether_mat});
    } else if (d.tether_metric == TetherMetric::geodesic) {
      // The nearest anchor along the edges: one search from all of them
      // (edge_paths.hpp; ties: the first, i.e. the lowest index).
      const detail::NearestAnchors na = detail::nearest_anchor_paths(s.positions, tri_edges, g.pinned);
      for (const std::size_t v : movable) {
        const std::size_t gv = std::size_t(g.first) + v;
        s.tethers.push_back(TetherDesc{Index(gv), g.pinned[std::size_t(na.anchor[gv])], na.distance[gv], d.tether_mat});
      }
    } else {
      // The nearest anchor (ties: the first, i.e. the lowest index).
      std::vector<Real> best_length(movable.size());
      std::vector<std::size_t> best(movable.size(), 0);
      for (std::size_t a = 0; a < pins; ++a) {
        lengths_from(a);
        for (std::size_t k = 0; k < movable.size(); ++k)
          if (a == 0 || from_anchor[movable[k]] < best_length[k]) {
            best_length[k] = from_anchor[movable[k]];
            best[k] = a;
          }
      }
      for (std::size_t k = 0; k < movable.size(); ++k)
        s.tethers.push_back(TetherDesc{g.first + Index(movable[k]), g.pinned[best[k]], best_length[k], d.tether_mat});
    }
  }
  if (d.collision_triangles)
    s.collision_triangles.insert(s.collision_triangles.end(), g.triangles.begin(), g.triangles.end());
  s.surface_triangles.insert(s.surface_triangles.end(), g.triangles.begin(), g.triangles.end());
  return g;
}

// ---------------------------------------------------------------------------
// Rope

Index add_rope(SceneDesc& s, const RopeDesc& d) {
  if (d.n < 2) throw SceneError("rope.n: need at least 2 particles, got " + std::to_string(d.n));
  if (!(d.spacing > Real(0)))
    throw SceneError("rope.spacing: must be > 0, got " + std::to_string(d.spacing));
  std::vector<Real> mass(std::size_t(d.n), d.mass);
  for (std::size_t k = 0; k < d.particle_masses.size(); ++k) {
    const ParticleMass& pm = d.particle_masses[k];
    const std::string at = "rope.particle_masses[" + std::to_string(k) + "]: ";
    if (pm.i < 0 || pm.i >= d.n)
      throw SceneError(at + "particle " + std::to_string(pm.i) + " is outside [0, " + std::to_string(d.n) + ")");
    if (!(pm.mass > Real(0)) || !std::isfinite(pm.mass))
      throw SceneError(at + "mass must be finite and > 0, got " + format_value(double(pm.mass)));
    if (d.pin_first && pm.i == 0)
      throw SceneError(at + "particle 0 is pinned (mass 0); a pinned particle has no mass to set");
    mass[std::size_t(pm.i)] = pm.mass;
  }
  if (!d.velocity.allFinite()) throw SceneError("rope.velocity: must be finite, got " + format_vec(d.velocity));
  const Index first = s.num_particles();
  for (int k = 0; k < d.n; ++k) {
    const bool pin = d.pin_first && k == 0;
    const Index i = s.add_particle(d.start + (Real(k) * d.spacing) * d.dir, pin ? Real(0) : mass[std::size_t(k)],
                                   d.radius, pin ? Vec3(Vec3::Zero()) : d.velocity);
    if (pin) s.pins.push_back(PinDesc{i, std::nullopt, Material{}});
    if (k > 0) s.distances.push_back(DistanceDesc{i - 1, i, d.spacing, d.mat});
  }
  return first;
}

// ---------------------------------------------------------------------------
// Tetrahedral box

TetBox add_tet_box(SceneDesc& s, const TetBoxDesc& d) {
  if (d.nx < 1 || d.ny < 1 || d.nz < 1)
    throw SceneError("tet_box.nx/ny/nz: need at least 1 cell per axis, got " +
                     std::to_string(d.nx) + " x " + std::to_string(d.ny) + " x " +
                     std::to_string(d.nz));
  check_positive("tet_box.size.x", d.size.x());
  check_positive("tet_box.size.y", d.size.y());
  check_positive("tet_box.size.z", d.size.z());
  if (!d.origin.allFinite()) throw SceneError("tet_box.origin: must be finite");
  check_non_negative("tet_box.mass", d.mass);
  check_non_negative("tet_box.bulk_modulus", d.bulk_modulus);
  TetBox b;
  b.first = s.num_particles();
  b.nx = d.nx;
  b.ny = d.ny;
  b.nz = d.nz;
  const std::size_t n = std::size_t(d.nx + 1) * std::size_t(d.ny + 1) * std::size_t(d.nz + 1);
  std::vector<char> pin(n, 0);
  for (const auto& [i, j, k] : d.pinned) {
    if (i < 0 || i > d.nx || j < 0 || j > d.ny || k < 0 || k > d.nz)
      throw SceneError("tet_box.pinned: (" + std::to_string(i) + ", " + std::to_string(j) + ", " +
                       std::to_string(k) + ") is outside the particle grid [0, " +
                       std::to_string(d.nx) + "] x [0, " + std::to_string(d.ny) + "] x [0, " +
                       std::to_string(d.nz) + "]");
    pin[std::size_t(b.at(i, j, k) - b.first)] = 1;
  }
  const Vec3 cell(d.size.x() / Real(d.nx), d.size.y() / Real(d.ny), d.size.z() / Real(d.nz));
  std::vector<Vec3> x(n);
  for (int k = 0; k <= d.nz; ++k)
    for (int j = 0; j <= d.ny; ++j)
      for (int i = 0; i <= d.nx; ++i)
        x[std::size_t(b.at(i, j, k) - b.first)] =
            d.origin + Vec3(Real(i) * cell.x(), Real(j) * cell.y(), Real(k) * cell.z());

  // Tets, as local corner codes c = a + 2b + 4c for corner (a, b, c) of a cell.
  using Tet = std::array<int, 4>;
  // Six: the monotone paths 000 -> 111, one per order of the axes.
  static constexpr Tet kSix[6] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                  {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
  // Five, central tet on the odd corners {1, 2, 4, 7}: corner tets at the
  // even corners 0, 3, 5, 6, each with its three edge neighbours.
  static constexpr Tet kFiveA[5] = {{1, 2, 4, 7}, {0, 1, 2, 4}, {3, 1, 2, 7},
                                    {5, 1, 4, 7}, {6, 2, 4, 7}};
  // Mirrored: central tet on the even corners {0, 3, 5, 6}.
  static constexpr Tet kFiveB[5] = {{0, 3, 5, 6}, {1, 0, 3, 5}, {2, 0, 3, 6},
                                    {4, 0, 5, 6}, {7, 3, 5, 6}};
  for (int k = 0; k < d.nz; ++k)
    for (int j = 0; j < d.ny; ++j)
      for (int i = 0; i < d.nx; ++i) {
        auto corner = [&](int c) { return b.at(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)); };
        // The central tet of the five-split must be the cell corners whose
        // global index sum i+j+k is odd, so that both cells sharing a face
        // cut it along the same diagonal. Local corner c has global parity
        // (i+j+k) + (bits of c): the local odd corners are globally odd when
        // i+j+k is even.
        const Tet* tets = kSix;
        int count = 6;
        if (d.split == TetSplit::five) {
          tets = (i + j + k) % 2 == 0 ? kFiveA : kFiveB;
          count = 5;
        }
        for (int t = 0; t < count; ++t) {
          std::array<Index, 4> p{corner(tets[t][0]), corner(tets[t][1]), corner(tets[t][2]),
                                 corner(tets[t][3])};
          auto pos = [&](int c) { return x[std::size_t(p[c] - b.first)]; };
          // Positive orientation: swap two corners of a negatively wound tet.
          if (TetVolume::volume(pos(0), pos(1), pos(2), pos(3)) < Real(0)) std::swap(p[2], p[3]);
          b.tets.push_back(p);
        }
      }

  // Masses lumped by volume, scaled to `mass` over the movable particles.
  std::vector<Real> w(n, Real(0));
  std::vector<Real> vol(b.tets.size());
  for (std::size_t t = 0; t < b.tets.size(); ++t) {
    const auto& p = b.tets[t];
    auto pos = [&](int c) { return x[std::size_t(p[c] - b.first)]; };
    vol[t] = TetVolume::volume(pos(0), pos(1), pos(2), pos(3));
    for (Index q : p) w[std::size_t(q - b.first)] += vol[t] / Real(4);
  }
  Real movable = 0;
  for (std::size_t v = 0; v < n; ++v)
    if (!pin[v]) movable += w[v];
  for (std::size_t v = 0; v < n; ++v) {
    const Real m = pin[v] || !(movable > Real(0)) ? Real(0) : d.mass * w[v] / movable;
    const Index q = s.add_particle(x[v], m, d.radius);
    if (pin[v]) s.pins.push_back(PinDesc{q, std::nullopt, Material{}});
  }

  // Volume constraints.
  s.tets.reserve(s.tets.size() + b.tets.size());
  for (std::size_t t = 0; t < b.tets.size(); ++t) {
    Material mat = d.volume_mat;
    if (d.bulk_modulus > Real(0)) mat.compliance = vol[t] / d.bulk_modulus;  // m^6/J = m^3 / Pa
    s.tets.push_back(TetVolumeDesc{b.tets[t], std::nullopt, mat});
  }

  // Edges: every tet edge once.
  if (d.edges) {
    std::vector<std::array<Index, 2>> e;
    e.reserve(6 * b.tets.size());
    for (const auto& p : b.tets)
      for (int u = 0; u < 4; ++u)
        for (int v = u + 1; v < 4; ++v) e.push_back(edge_key(p[u], p[v]));
    std::sort(e.begin(), e.end());
    e.erase(std::unique(e.begin(), e.end()), e.end());
    s.distances.reserve(s.distances.size() + e.size());
    for (const auto& k : e) s.distances.push_back(DistanceDesc{k[0], k[1], std::nullopt, d.edge_mat});
  }

  // Boundary: faces that belong to a single tet, oriented outward. For a
  // positive tet (p0, p1, p2, p3) the outward faces are (0,2,1), (0,1,3),
  // (0,3,2), (1,2,3).
  struct Face {
    std::array<Index, 3> key;  // sorted
    Triangle tri;              // oriented
  };
  std::vector<Face> faces;
  faces.reserve(4 * b.tets.size());
  static constexpr int kFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& p : b.tets)
    for (const auto& f : kFaces) {
      Triangle tri{p[f[0]], p[f[1]], p[f[2]]};
      std::array<Index, 3> key = tri;
      std::sort(key.begin(), key.end());
      faces.push_back(Face{key, tri});
    }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& c) { return a.key < c.key; });
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i == 1) b.surface.push_back(faces[i].tri);
    i = j;
  }
  s.surface_triangles.insert(s.surface_triangles.end(), b.surface.begin(), b.surface.end());
  return b;
}

// ---------------------------------------------------------------------------
// Triangle mesh

MeshResult add_triangle_mesh(SceneDesc& s, const TriangleMesh& mesh, const TriangleMeshDesc& d) {
  const std::string& name = d.name;
  const int base = d.index_base;
  const auto nv = static_cast<Index>(mesh.positions.size());
  if (mesh.positions.empty()) fail(name, "has no vertices");
  if (mesh.triangles.empty()) fail(name, "has no triangles");
  check_positive(name + ": scale", d.scale);
  if (!d.offset.allFinite()) fail(name, "offset must be finite");
  check_non_negative(name + ": mass", d.mass);
  if (d.kind == MeshKind::closed_surface) check_positive(name + ": pressure", d.pressure);
  for (Index v = 0; v < nv; ++v)
    if (!mesh.positions[std::size_t(v)].allFinite())
      fail(name, "vertex " + std::to_string(v + base) + " has a non-finite position");
  std::vector<char> used(std::size_t(nv), 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    for (int c = 0; c < 3; ++c) {
      if (tri[c] < 0 || tri[c] >= nv)
        fail(name, "triangle " + std::to_string(t + std::size_t(base)) + " uses vertex " + std::to_string(tri[c] + base) +
                       ", but the vertices are numbered " + std::to_string(base) + " to " +
                       std::to_string(nv - 1 + base));
      used[std::size_t(tri[c])] = 1;
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
      fail(name, "triangle " + std::to_string(t + std::size_t(base)) + " (" + std::to_string(tri[0] + base) + ", " +
                     std::to_string(tri[1] + base) + ", " + std::to_string(tri[2] + base) +
                     ") repeats a vertex");
  }
  for (Index v = 0; v < nv; ++v)
    if (!used[std::size_t(v)])
      fail(name, "vertex " + std::to_string(v + base) +
                     " belongs to no triangle, so it would get no mass; remove it");

  // Topology checks (before anything is added to the scene).
  const std::vector<std::array<Index, 4>> hinges = mesh_hinges(mesh.triangles, name, base);
  if (d.kind == MeshKind::closed_surface) {
    const std::vector<HalfEdge> he = sorted_half_edges(mesh.triangles);
    for (std::size_t i = 0; i < he.size();) {
      std::size_t j = i + 1;
      while (j < he.size() && he[j].key == he[i].key) ++j;
      // mesh_hinges has already rejected more than two.
      if (j - i == 1)
        fail(name, "is not closed: edge " + edge_name(he[i].a, he[i].b, base) +
                       " belongs only to triangle " + std::to_string(he[i].tri + std::size_t(base)) +
                       " (a closed surface needs every edge in exactly two triangles)");
      if (he[i].a == he[i + 1].a)
        fail(name, "is not consistently oriented: triangles " + std::to_string(he[i].tri + std::size_t(base)) + " and " +
                       std::to_string(he[i + 1].tri + std::size_t(base)) + " both traverse edge " +
                       edge_name(he[i].a, he[i].b, base) + " in the same direction");
      i = j;
    }
    // Enclosed volume (1/6) sum (a x b).c, relative to vertex 0.
    Real vol = 0;
    const Vec3 o = mesh.positions[0];
    for (const Triangle& t : mesh.triangles)
      vol += (mesh.positions[std::size_t(t[0])] - o)
                 .cross(mesh.positions[std::size_t(t[1])] - o)
                 .dot(mesh.positions[std::size_t(t[2])] - o);
    vol /= Real(6);
    if (!(vol > Real(0)))
      fail(name, "encloses a volume of " + num(vol) +
                     " (mesh units^3): its triangles must wind counter-clockwise seen from "
                     "outside; reverse the winding of every face");
  }

  // Masses lumped by area.
  std::vector<Real> area(std::size_t(nv), Real(0));
  Real total = 0;
  for (const Triangle& t : mesh.triangles) {
    const Vec3& a = mesh.positions[std::size_t(t[0])];
    const Real ar =
        Real(0.5) * (mesh.positions[std::size_t(t[1])] - a).cross(mesh.positions[std::size_t(t[2])] - a).norm();
    for (Index v : t) area[std::size_t(v)] += ar / Real(3);
    total += ar;
  }
  if (!(total > Real(0))) fail(name, "has zero total area, so the mass cannot be distributed");

  MeshResult r;
  r.first = s.num_particles();
  for (Index v = 0; v < nv; ++v)
    s.add_particle(d.offset + d.scale * mesh.positions[std::size_t(v)],
                   d.mass * area[std::size_t(v)] / total, d.radius);
  auto shift = [&](Index v) { return r.first + v; };
  r.triangles.reserve(mesh.triangles.size());
  for (const Triangle& t : mesh.triangles) r.triangles.push_back({shift(t[0]), shift(t[1]), shift(t[2])});
  r.edges = triangle_edges(r.triangles);
  s.distances.reserve(s.distances.size() + r.edges.size());
  for (const auto& e : r.edges) s.distances.push_back(DistanceDesc{e[0], e[1], std::nullopt, d.edge_mat});
  r.hinges = hinges.size();
  if (d.bending != HingeBending::none) {
    std::vector<std::array<Index, 4>> h = hinges;
    for (auto& q : h)
      for (Index& v : q) v = shift(v);
    add_hinges(s, h, d.bending, d.bend_mat);
  }
  if (d.kind == MeshKind::closed_surface)
    s.global_volumes.push_back(GlobalVolumeDesc{r.triangles, d.pressure, d.volume_mat});
  s.surface_triangles.insert(s.surface_triangles.end(), r.triangles.begin(), r.triangles.end());
  return r;
}

}  // namespace xpbd
