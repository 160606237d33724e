// Hierarchical position-based dynamics (hierarchy.hpp).
#include "hierarchy.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "xpbd/model.hpp"
#include "xpbd/state.hpp"

namespace xpbd::detail {
namespace {

constexpr Real kInf = std::numeric_limits<Real>::infinity();
constexpr int kMaxLevels = 12;
constexpr std::size_t kMinParticles = 8;
// A child keeps at most this many parents (the nearest by rest length), so
// that a particle joined to many (a fan's hub) costs at most 120 coarse
// edges, not the square of its degree.
constexpr std::size_t kMaxParents = 16;

// One level's graph: nodes as model indices, adjacency by position with the
// edge's rest length.
struct Graph {
  std::vector<Index> node;
  std::vector<Real> mass;  // kg; infinite for inverse mass 0
  std::vector<std::vector<std::pair<Index, Real>>> adj;
};

// Joins a and b (positions in g), keeping the shorter rest of a repeated pair.
void add_edge(Graph& g, Index a, Index b, Real rest) {
  if (a == b) return;
  auto link = [&](Index from, Index to) {
    auto& e = g.adj[static_cast<std::size_t>(from)];
    auto it = std::find_if(e.begin(), e.end(), [&](const auto& n) { return n.first == to; });
    if (it == e.end()) e.emplace_back(to, rest);
    else it->second = std::min(it->second, rest);
  };
  link(a, b);
  link(b, a);
}

Graph fine_graph(const Model& m) {
  const auto& dist = m.get<Distance>();
  std::vector<Index> pos(static_cast<std::size_t>(m.num_particles()), -1);
  Graph g;
  for (const Distance& d : dist)
    for (Index p : d.p)
      if (pos[static_cast<std::size_t>(p)] < 0) pos[static_cast<std::size_t>(p)] = 0;
  for (Index p = 0; p < m.num_particles(); ++p)
    if (pos[static_cast<std::size_t>(p)] == 0) {
      pos[static_cast<std::size_t>(p)] = static_cast<Index>(g.node.size());
      g.node.push_back(p);
      const Real w = m.inv_mass[static_cast<std::size_t>(p)];
      g.mass.push_back(w > Real(0) ? Real(1) / w : kInf);
    }
  g.adj.resize(g.node.size());
  for (const Distance& d : dist)
    add_edge(g, pos[static_cast<std::size_t>(d.p[0])], pos[static_cast<std::size_t>(d.p[1])], d.rest);
  return g;
}

// Coarsens g into a level (and the next level's graph). Returns false when
// the coarse set would not be worth a level.
bool coarsen(const Graph& g, HierarchyLevel& lev, Graph& next) {
  const std::size_t n = g.node.size();
  // Maximal independent set: inverse mass 0 first, then in order.
  enum : std::uint8_t { kFree, kCoarse, kFine };
  std::vector<std::uint8_t> mark(n, kFree);
  auto visit = [&](std::size_t i) {
    if (mark[i] != kFree) return;
    mark[i] = kCoarse;
    for (const auto& [j, r] : g.adj[i]) mark[static_cast<std::size_t>(j)] = kFine;
  };
  for (std::size_t i = 0; i < n; ++i)
    if (std::isinf(g.mass[i])) visit(i);
  for (std::size_t i = 0; i < n; ++i) visit(i);
  std::vector<Index> cpos(n, -1);
  for (std::size_t i = 0; i < n; ++i)
    if (mark[i] == kCoarse) {
      cpos[i] = static_cast<Index>(next.node.size());
      next.node.push_back(g.node[i]);
      next.mass.push_back(g.mass[i]);
    }
  const std::size_t nc = next.node.size();
  if (nc < kMinParticles || Real(nc) > Real(0.9) * Real(n)) return false;
  next.adj.assign(nc, {});
  // Children: weights 1/rest towards their coarse neighbours; mass to them;
  // each pair of a child's parents is a coarse edge of rest the path's.
  std::vector<std::pair<Index, Real>> parents;
  for (std::size_t i = 0; i < n; ++i) {
    if (mark[i] == kCoarse) continue;
    parents.clear();
    for (const auto& [j, r] : g.adj[i])
      if (mark[static_cast<std::size_t>(j)] == kCoarse)
        parents.emplace_back(j, Real(1) / std::max(r, std::numeric_limits<Real>::min()));
    if (parents.empty()) continue;  // unreachable: the set is maximal
    if (parents.size() > kMaxParents) {
      auto nearer = [](const auto& a, const auto& b) {
        return a.second > b.second || (a.second == b.second && a.first < b.first);
      };
      std::partial_sort(parents.begin(), parents.begin() + kMaxParents, parents.end(), nearer);
      parents.resize(kMaxParents);
    }
    Real sum = 0;
    for (const auto& [j, w] : parents) sum += w;
    const bool movable = !std::isinf(g.mass[i]);
    if (movable) lev.child.push_back(g.node[i]);
    for (const auto& [j, w] : parents) {
      const Real wn = w / sum;
      if (movable) {
        lev.parent.push_back(g.node[static_cast<std::size_t>(j)]);
        lev.weight.push_back(wn);
        next.mass[static_cast<std::size_t>(cpos[static_cast<std::size_t>(j)])] += wn * g.mass[i];
      }
    }
    if (movable) lev.parent_begin.push_back(static_cast<Index>(lev.parent.size()));
    for (std::size_t a = 0; a < parents.size(); ++a)
      for (std::size_t b = a + 1; b < parents.size(); ++b) {
        const auto& [pa, wa] = parents[a];
        const auto& [pb, wb] = parents[b];
        add_edge(next, cpos[static_cast<std::size_t>(pa)], cpos[static_cast<std::size_t>(pb)],
                 Real(1) / wa + Real(1) / wb);
      }
  }
  lev.particles = next.node;
  lev.inv_mass.resize(nc);
  for (std::size_t c = 0; c < nc; ++c) lev.inv_mass[c] = std::isinf(next.mass[c]) ? Real(0) : Real(1) / next.mass[c];
  for (std::size_t c = 0; c < nc; ++c)
    for (const auto& [d, r] : next.adj[c])
      if (static_cast<std::size_t>(d) > c) {
        lev.edges.push_back({static_cast<Index>(c), d});
        lev.rest.push_back(r);
      }
  return !lev.edges.empty();
}

}  // namespace

std::shared_ptr<const Hierarchy> build_hierarchy(const Model& m) {
  auto h = std::make_shared<Hierarchy>();
  h->num_particles = m.num_particles();
  h->num_distance = m.get<Distance>().size();
  Graph g = fine_graph(m);
  while (h->levels.size() < static_cast<std::size_t>(kMaxLevels)) {
    HierarchyLevel lev;
    Graph next;
    if (!coarsen(g, lev, next)) break;
    h->levels.push_back(std::move(lev));
    g = std::move(next);
  }
  return h;
}

void hierarchy_pass(const Model& m, State& s, Real slack) {
  if (s.hierarchy == nullptr || s.hierarchy->num_particles != m.num_particles() ||
      s.hierarchy->num_distance != m.get<Distance>().size())
    s.hierarchy = build_hierarchy(m);
  const Hierarchy& hier = *s.hierarchy;
  if (hier.levels.empty()) return;
  s.hierarchy_x.assign(s.x.begin(), s.x.end());
  const std::vector<Vec3>& before = s.hierarchy_x;
  std::vector<Vec3>& x = s.x;
  const Real stretch = Real(1) + slack;
  for (std::size_t L = hier.levels.size(); L-- > 0;) {
    const HierarchyLevel& lev = hier.levels[L];
    for (std::size_t e = 0; e < lev.edges.size(); ++e) {
      const auto [a, b] = lev.edges[e];
      const Real wa = lev.inv_mass[static_cast<std::size_t>(a)], wb = lev.inv_mass[static_cast<std::size_t>(b)];
      const Real w = wa + wb;
      if (!(w > Real(0))) continue;
      Vec3& xa = x[static_cast<std::size_t>(lev.particles[static_cast<std::size_t>(a)])];
      Vec3& xb = x[static_cast<std::size_t>(lev.particles[static_cast<std::size_t>(b)])];
      const Vec3 d = xa - xb;
      const Real len = d.norm();
      const Real target = lev.rest[e] * stretch;
      if (!(len > target)) continue;
      const Vec3 corr = d * ((len - target) / (len * w));
      xa -= wa * corr;
      xb += wb * corr;
    }
    for (std::size_t k = 0; k < lev.child.size(); ++k) {
      Vec3 delta = Vec3::Zero();
      for (Index j = lev.parent_begin[k]; j < lev.parent_begin[k + 1]; ++j) {
        const auto p = static_cast<std::size_t>(lev.parent[static_cast<std::size_t>(j)]);
        delta += lev.weight[static_cast<std::size_t>(j)] * (x[p] - before[p]);
      }
      x[static_cast<std::size_t>(lev.child[k])] += delta;
    }
  }
}

}  // namespace xpbd::detail
