// Shortest paths along a mesh's edges: the geodesic lengths of tethers
// (builders.cpp). Dijkstra's search with a binary heap, O(E log V) per
// search; the nearest of many anchors takes one search from all of them
// (a cloth of 1e5 particles pinned along a 100-particle edge: 9.2 s with a
// search per anchor, Release).
#include "edge_paths.hpp"

#include <limits>
#include <queue>
#include <tuple>

#include "xpbd/builders.hpp"

namespace xpbd {
namespace {

// Adjacency in compressed rows: the neighbours of v are nbr[start[v],
// start[v+1]).
struct Adjacency {
  std::vector<std::size_t> start;
  std::vector<Index> nbr;
};

Adjacency adjacency(std::size_t n, const std::vector<std::array<Index, 2>>& edges) {
  Adjacency g;
  g.start.assign(n + 1, 0);
  for (const auto& e : edges) {
    ++g.start[std::size_t(e[0]) + 1];
    ++g.start[std::size_t(e[1]) + 1];
  }
  for (std::size_t v = 0; v < n; ++v) g.start[v + 1] += g.start[v];
  g.nbr.resize(g.start[n]);
  std::vector<std::size_t> fill(g.start.begin(), g.start.end() - 1);
  for (const auto& e : edges) {
    g.nbr[fill[std::size_t(e[0])]++] = e[1];
    g.nbr[fill[std::size_t(e[1])]++] = e[0];
  }
  return g;
}

}  // namespace

std::vector<Real> edge_path_distances(const std::vector<Vec3>& x,
                                      const std::vector<std::array<Index, 2>>& edges,
                                      Index source) {
  const std::size_t n = x.size();
  const Adjacency g = adjacency(n, edges);
  std::vector<Real> dist(n, std::numeric_limits<Real>::infinity());
  using Item = std::pair<Real, Index>;  // (distance, vertex), smallest first
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  dist[std::size_t(source)] = 0;
  queue.push({Real(0), source});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[std::size_t(v)]) continue;  // stale entry
    for (std::size_t k = g.start[std::size_t(v)]; k < g.start[std::size_t(v) + 1]; ++k) {
      const Index w = g.nbr[k];
      const Real dw = d + (x[std::size_t(w)] - x[std::size_t(v)]).norm();
      if (dw < dist[std::size_t(w)]) {
        dist[std::size_t(w)] = dw;
        queue.push({dw, w});
      }
    }
  }
  return dist;
}

namespace detail {

NearestAnchors nearest_anchor_paths(const std::vector<Vec3>& x, const std::vector<std::array<Index, 2>>& edges,
                                    const std::vector<Index>& anchors) {
  const std::size_t n = x.size();
  const Adjacency g = adjacency(n, edges);
  NearestAnchors r;
  r.distance.assign(n, std::numeric_limits<Real>::infinity());
  r.anchor.assign(n, -1);
  using Item = std::tuple<Real, Index, Index>;  // (distance, anchor, vertex), smallest first
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  auto better = [&](Real d, Index a, std::size_t v) {
    return d < r.distance[v] || (d == r.distance[v] && a < r.anchor[v]);
  };
  for (std::size_t a = 0; a < anchors.size(); ++a) {
    const auto v = std::size_t(anchors[a]);
    if (r.anchor[v] >= 0) continue;  // listed twice: the first counts
    r.distance[v] = 0;
    r.anchor[v] = Index(a);
    queue.push({Real(0), Index(a), Index(v)});
  }
  while (!queue.empty()) {
    const auto [d, a, v] = queue.top();
    queue.pop();
    if (d != r.distance[std::size_t(v)] || a != r.anchor[std::size_t(v)]) continue;  // stale entry
    for (std::size_t k = g.start[std::size_t(v)]; k < g.start[std::size_t(v) + 1]; ++k) {
      const Index w = g.nbr[k];
      const Real dw = d + (x[std::size_t(w)] - x[std::size_t(v)]).norm();
      if (better(dw, a, std::size_t(w))) {
        r.distance[std::size_t(w)] = dw;
        r.anchor[std::size_t(w)] = a;
        queue.push({dw, a, w});
      }
    }
  }
  return r;
}

}  // namespace detail
}  // namespace xpbd
