// The collision triangles' hierarchy: built by FCL, refitted and walked
// here (triangle_bvh.hpp).
#include "triangle_bvh.hpp"

#include <algorithm>
#include <cstddef>
#include <bit>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "xpbd/workers.hpp"

#include <fcl/math/bv/utility.h>  // fit(), which BVH_model-inl.h uses
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/AABB.h>

namespace xpbd_bullet::detail {

namespace {
using Box = fcl::AABB<double>;  // FCL in double in both builds: the boxes only filter
using Point = fcl::Vector3<double>;
Point point(const xpbd::Vec3& p) { return Point(double(p.x()), double(p.y()), double(p.z())); }

// A node of the tree in depth-first order: an inner node's left child
// follows it, and `escape` is the first node after its subtree (its right
// child is its left child's escape). The box in single precision
// (to_float; 32 bytes a node, not 56: the refit and the walks touch 43 %
// fewer bytes; a 128 x 128 cloth's 64,500 nodes take 2.1 MB, not 3.6).
using Box3f = Eigen::Vector3f;
struct Node {
  Box3f lo, hi;  // the swept box, holding the triangle's (a leaf) or the children's
  int escape;
  int tri;  // the triangle of a leaf; -1 for an inner node
};
static_assert(sizeof(Node) == 32);
// query() loads four floats from lo and from hi.
static_assert(offsetof(Node, hi) == 12 && offsetof(Node, escape) == 24);

// A box in single precision: each coordinate rounded to the nearest float.
// Rounding never reverses an order (a <= b gives float(a) <= float(b)), and
// the nodes' and the queries' boxes are rounded alike; so a node whose
// rounded box misses the rounded query's truly misses it, and no triangle
// whose box overlaps the query's is lost. Triangles whose boxes miss it by
// less than the rounding may be returned too.
Box3f to_float(const xpbd::Vec3& v) { return v.cast<float>(); }
}  // namespace

struct TriangleBvh::Impl {
  std::vector<std::array<xpbd::Index, 3>> tris;  // what the tree was built for
  const std::array<xpbd::Index, 3>* tris_at = nullptr;  // the caller's vector, at the last update
  std::vector<Node> nodes;
  bool built = false;
  std::vector<int> above, roots;  // scratch of a refit split over threads
};

namespace {
// A refit on a pool splits the tree under its top kSplitDepth levels (up to
// 2^kSplitDepth subtrees), for trees of at least kSplitFrom nodes.
constexpr int kSplitDepth = 3;
constexpr std::size_t kSplitFrom = 4096;
}  // namespace

TriangleBvh::TriangleBvh() : impl_(std::make_unique<Impl>()) {}
TriangleBvh::~TriangleBvh() = default;

namespace {

// FCL's tree (fcl::BVHModel, its default mean split), built over the
// points, as nodes in depth-first order.
std::vector<Node> build(const std::vector<std::array<xpbd::Index, 3>>& tris, const std::vector<Point>& points) {
  if (tris.empty()) return {};
  fcl::BVHModel<Box> model;
  std::vector<fcl::Triangle> t;
  t.reserve(tris.size());
  for (const auto& tri : tris) t.emplace_back(std::size_t(tri[0]), std::size_t(tri[1]), std::size_t(tri[2]));
  model.beginModel(int(t.size()), int(points.size()));
  model.addSubModel(points, t);
  model.endModel();
  // Depth first, left before right (FCL's nodes: first_child < 0 marks a
  // leaf, of triangle -first_child - 1; the right child is first_child + 1).
  const fcl::BVNode<Box>* const fcl_nodes = &model.getBV(0);
  std::vector<int> from;  // FCL's node of each of ours
  from.reserve(std::size_t(model.getNumBVs()));
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const int id = stack.back();
    stack.pop_back();
    from.push_back(id);
    const int c = fcl_nodes[id].first_child;
    if (c >= 0) {
      stack.push_back(c + 1);
      stack.push_back(c);
    }
  }
  std::vector<Node> nodes(from.size());
  for (std::size_t i = from.size(); i-- > 0;) {
    const int c = fcl_nodes[from[i]].first_child;
    nodes[i].tri = c < 0 ? -c - 1 : -1;
    // A leaf ends its subtree; an inner node's ends where its right
    // child's does, which starts where its left child's (at i + 1) ends.
    nodes[i].escape = c < 0 ? int(i) + 1 : nodes[std::size_t(nodes[i + 1].escape)].escape;
  }
  return nodes;
}

}  // namespace

void TriangleBvh::update(const std::vector<std::array<xpbd::Index, 3>>& tris, const std::vector<xpbd::Vec3>& x,
                         const std::vector<xpbd::Vec3>& lo, const std::vector<xpbd::Vec3>& hi,
                         xpbd::Workers* workers) {
  Impl& m = *impl_;
  // The same vector as last time (its address and size) holds the same
  // triangles: the bridge's systems never change theirs. Another one is
  // compared by content (a copy of a system's model).
  const bool same = m.built && tris.data() == m.tris_at && tris.size() == m.tris.size();
  if (!same && (!m.built || tris != m.tris)) {
    std::vector<Point> points(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) points[i] = point(x[i]);
    m.nodes = build(tris, points);
    m.tris = tris;
    m.built = true;
  }
  m.tris_at = tris.data();
  // The refit: each leaf's box is its triangle's, each inner node's is over
  // its two children's, last node first, so that children come before
  // their parent. With a pool, the subtrees under the top kSplitDepth
  // levels are refitted in parallel (each a range of nodes of its own),
  // then the nodes above them: the same boxes.
  std::vector<Node>& nodes = m.nodes;
  const auto refit = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = end; i-- > begin;) {
      Node& node = nodes[i];
      if (node.tri >= 0) {
        node.lo = to_float(lo[std::size_t(node.tri)]);
        node.hi = to_float(hi[std::size_t(node.tri)]);
      } else {
        const Node& l = nodes[i + 1];
        const Node& r = nodes[std::size_t(l.escape)];
        node.lo = l.lo.cwiseMin(r.lo);
        node.hi = l.hi.cwiseMax(r.hi);
      }
    }
  };
  if (workers == nullptr || workers->threads() < 2 || nodes.size() < kSplitFrom) {
    refit(0, nodes.size());
    return;
  }
  // The top levels' inner nodes (ascending: parents before children) and
  // the subtrees below them.
  std::vector<int>& above = m.above;
  std::vector<int>& roots = m.roots;
  above.clear();
  roots.assign(1, 0);
  for (int depth = 0; depth < kSplitDepth; ++depth) {
    std::vector<int> next;
    for (const int r : roots) {
      if (nodes[std::size_t(r)].tri >= 0) {
        next.push_back(r);  // a leaf stays a subtree of its own
        continue;
      }
      above.push_back(r);
      next.push_back(r + 1);
      next.push_back(nodes[std::size_t(r) + 1].escape);
    }
    roots.swap(next);
  }
  workers->run(static_cast<int>(roots.size()), [&](int k) {
    const std::size_t r = std::size_t(roots[std::size_t(k)]);
    refit(r, std::size_t(nodes[r].escape));
  });
  std::sort(above.begin(), above.end());
  for (std::size_t k = above.size(); k-- > 0;) refit(std::size_t(above[k]), std::size_t(above[k]) + 1);
}

void TriangleBvh::query(const xpbd::Vec3& lo, const xpbd::Vec3& hi, std::vector<int>& out) const {
  std::vector<std::uint64_t> marks;
  query(lo, hi, out, marks);
}

void TriangleBvh::query(const xpbd::Vec3& lo, const xpbd::Vec3& hi, std::vector<int>& out,
                        std::vector<std::uint64_t>& marks) const {
  const Impl& m = *impl_;
  // The query's box rounded as the nodes' (to_float).
  const Box3f a = to_float(lo), b = to_float(hi);
  if (marks.size() < (m.tris.size() + 63) / 64) marks.resize((m.tris.size() + 63) / 64, 0);
  // Depth first without a stack: a node whose box misses the query's skips
  // its subtree. Each triangle found is marked (one bit), then the marks
  // are read in ascending order and cleared: on a cloth, the triangles near
  // one body lie in a few rows, a few words of marks; a sort of the same
  // triangles took as long as the walk.
  std::size_t first = marks.size(), last = 0;
  const std::size_t count = m.nodes.size();
#if defined(__SSE__)
  // The box test in one compare per side: a node's lo and hi each load as
  // four floats (the fourth, the next field, is masked off). A NaN
  // compares false either way, as in the scalar test. 0.77 times the
  // walk's time on bench_triangles 64 x 64 (docs/search-costs.md).
  const __m128 qa = _mm_setr_ps(a.x(), a.y(), a.z(), 0.f), qb = _mm_setr_ps(b.x(), b.y(), b.z(), 0.f);
  const auto misses = [&](const Node& node) {
    const __m128 lo4 = _mm_loadu_ps(node.lo.data()), hi4 = _mm_loadu_ps(node.hi.data());
    return (_mm_movemask_ps(_mm_or_ps(_mm_cmplt_ps(qb, lo4), _mm_cmpgt_ps(qa, hi4))) & 7) != 0;
  };
#else
  const auto misses = [&](const Node& node) {
    return (b.array() < node.lo.array()).any() || (a.array() > node.hi.array()).any();
  };
#endif
  for (std::size_t i = 0; i < count;) {
    const Node& node = m.nodes[i];
    if (misses(node)) {
      i = std::size_t(node.escape);
      continue;
    }
    if (node.tri >= 0) {
      const std::size_t w = std::size_t(node.tri) >> 6;
      marks[w] |= std::uint64_t(1) << (unsigned(node.tri) & 63u);
      first = std::min(first, w);
      last = std::max(last, w);
    }
    ++i;
  }
  if (first > last) return;
  std::size_t found = 0;
  for (std::size_t w = first; w <= last; ++w) found += std::size_t(std::popcount(marks[w]));
  out.reserve(out.size() + found);  // the marks are cleared below, which must not throw
  for (std::size_t w = first; w <= last; ++w) {
    for (std::uint64_t bits = marks[w]; bits != 0; bits &= bits - 1)
      out.push_back(int(w * 64 + std::size_t(std::countr_zero(bits))));
    marks[w] = 0;
  }
}

}  // namespace xpbd_bullet::detail
