// The contact search's box filters (bullet_bridge/src): the list of boxes
// tested many at a time (box_list.hpp) against the one-at-a-time
// definition, and the triangles' hierarchy (triangle_bvh.hpp), whose boxes
// are kept in single precision and must never lose a triangle whose box
// overlaps the query's, however close to its edge.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "../../bullet_bridge/src/box_list.hpp"
#include "../../bullet_bridge/src/triangle_bvh.hpp"
#include "xpbd/types.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;

bool overlaps(const Vec3& lo, const Vec3& hi, const Vec3& blo, const Vec3& bhi) {
  for (int k = 0; k < 3; ++k)
    if (!(blo[k] <= hi[k] && bhi[k] >= lo[k])) return false;
  return true;
}

// Every list length from 0 to 9 (whole lanes and remainders in either
// precision), boxes that touch the query exactly, a NaN box, and a random
// subset of the triangles, taken by index or given directly: the positions
// returned are exactly those of the boxes that overlap, one at a time, in
// ascending order.
TEST(BoxList, ReturnsExactlyTheOverlappingBoxesInOrder) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-1, 1), size(0, 0.5);
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  for (int n = 0; n <= 9; ++n) {
    for (int round = 0; round < 50; ++round) {
      // 12 triangles' boxes; the list takes n of them, not in index order.
      std::vector<Vec3> lo(12), hi(12);
      for (int t = 0; t < 12; ++t) {
        lo[std::size_t(t)] = Vec3(Real(coord(rng)), Real(coord(rng)), Real(coord(rng)));
        hi[std::size_t(t)] = lo[std::size_t(t)] + Vec3(Real(size(rng)), Real(size(rng)), Real(size(rng)));
      }
      const Vec3 qlo(Real(coord(rng)), Real(coord(rng)), Real(coord(rng)));
      const Vec3 qhi = qlo + Vec3::Constant(Real(0.6));
      lo[0] = Vec3(qhi.x(), qlo.y(), qlo.z());  // touches the query's face x = qhi.x
      hi[0] = lo[0] + Vec3::Constant(Real(0.1));
      hi[1] = Vec3(qlo.x(), qhi.y(), qhi.z());  // touches its corner at (qlo.x, ...)
      lo[1] = hi[1] - Vec3::Constant(Real(0.1));
      lo[2].y() = nan;
      std::vector<int> tris;
      for (int k = 0; k < n; ++k) tris.push_back((5 * k + round) % 12);
      xpbd_bullet::detail::BoxList list;
      list.assign(tris, lo, hi);
      ASSERT_EQ(list.size(), tris.size());
      std::vector<int> got, want;
      list.overlapping(qlo, qhi, got);
      for (int k = 0; k < n; ++k)
        if (overlaps(qlo, qhi, lo[std::size_t(tris[std::size_t(k)])], hi[std::size_t(tris[std::size_t(k)])]))
          want.push_back(k);
      ASSERT_EQ(got, want) << "n " << n << ", round " << round;
      // The same boxes given directly, in the list's order.
      std::vector<Vec3> own_lo, own_hi;
      for (const int t : tris) {
        own_lo.push_back(lo[std::size_t(t)]);
        own_hi.push_back(hi[std::size_t(t)]);
      }
      xpbd_bullet::detail::BoxList direct;
      direct.assign(own_lo, own_hi);
      ASSERT_EQ(direct.size(), tris.size());
      got.clear();
      direct.overlapping(qlo, qhi, got);
      ASSERT_EQ(got, want) << "given directly: n " << n << ", round " << round;
    }
  }
}

// A 20 x 20 grid of triangles whose boxes are given at coordinates that
// float cannot hold (multiples of 0.1 plus 1e-12); each query box touches
// one triangle's box exactly on one face, so that the triangle is kept only
// if the query is rounded to float as the nodes are (a query edge moved in
// by 1e-9 m loses it). Every triangle whose box overlaps is returned, in
// ascending order, and none 1 mm away.
// An n x n grid of squares 0.1 m wide, two triangles each, and each
// triangle's box shifted by 1e-12 m (a coordinate float cannot hold).
struct Grid {
  std::vector<Vec3> x, lo, hi;
  std::vector<std::array<xpbd::Index, 3>> tris;
  explicit Grid(int n) {
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) x.emplace_back(Real(0.1) * Real(i), 0, Real(0.1) * Real(j));
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const xpbd::Index a = j * (n + 1) + i, b = a + 1, c = a + n + 1;
        tris.push_back({a, b, c});
        tris.push_back({b, c + 1, c});
      }
    lo.resize(tris.size());
    hi.resize(tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) {
      lo[t] = x[std::size_t(tris[t][0])].cwiseMin(x[std::size_t(tris[t][1])]).cwiseMin(x[std::size_t(tris[t][2])]);
      hi[t] = x[std::size_t(tris[t][0])].cwiseMax(x[std::size_t(tris[t][1])]).cwiseMax(x[std::size_t(tris[t][2])]);
      lo[t].array() += Real(1e-12);
      hi[t].array() += Real(1e-12);
    }
  }
};

TEST(TriangleBvh, NeverLosesATriangleWhoseBoxTouchesTheQuery) {
  const Grid g(20);
  const auto& [x, lo, hi, tris] = g;
  xpbd_bullet::detail::TriangleBvh bvh;
  bvh.update(tris, x, lo, hi);
  int checked = 0;
  for (std::size_t t = 0; t < tris.size(); t += 7) {
    for (int side = 0; side < 2; ++side) {
      // A small box beyond the triangle's box in x, touching its face.
      Vec3 qlo = lo[t], qhi = hi[t];
      if (side == 0) {
        qlo.x() = hi[t].x();
        qhi.x() = hi[t].x() + Real(0.01);
      } else {
        qhi.x() = lo[t].x();
        qlo.x() = lo[t].x() - Real(0.01);
      }
      std::vector<int> got, want;
      bvh.query(qlo, qhi, got);
      for (std::size_t u = 0; u < tris.size(); ++u)
        if (overlaps(qlo, qhi, lo[u], hi[u])) want.push_back(int(u));
      ASSERT_FALSE(want.empty());
      // Every overlapping triangle, in ascending order, and perhaps some
      // within float rounding of the query, but none 1 mm away.
      std::size_t w = 0;
      for (const int g : got) {
        if (w < want.size() && g == want[w]) {
          ++w;
          continue;
        }
        const Vec3 pad = Vec3::Constant(Real(1e-3));
        EXPECT_TRUE(overlaps(qlo - pad, qhi + pad, lo[std::size_t(g)], hi[std::size_t(g)])) << "triangle " << g;
      }
      EXPECT_EQ(w, want.size()) << "triangle " << t << ", side " << side;
      EXPECT_TRUE(std::is_sorted(got.begin(), got.end()));
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

// The query with the caller's marks (the contact search keeps one per
// thread): random boxes, one marks vector for all of them, against a fresh
// one per query. The same triangles each time, appended after what `out`
// held, in ascending order, every overlapping one among them; and the
// marks are all clear after each query (a mark left set would add its
// triangle to every later query).
TEST(TriangleBvh, SharedMarksGiveTheSameTrianglesAndAreLeftClear) {
  const Grid g(30);
  xpbd_bullet::detail::TriangleBvh bvh;
  bvh.update(g.tris, g.x, g.lo, g.hi);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> at(-0.2, 3.2), size(0.0, 0.8);
  std::vector<std::uint64_t> marks;
  int nonempty = 0;
  for (int round = 0; round < 300; ++round) {
    Vec3 qlo(Real(at(rng)), Real(-0.01), Real(at(rng)));
    const Vec3 qhi = qlo + Vec3(Real(size(rng)), Real(0.02), Real(size(rng)));
    std::vector<int> fresh, shared{-5};  // shared: something held before
    bvh.query(qlo, qhi, fresh);
    bvh.query(qlo, qhi, shared, marks);
    ASSERT_EQ(shared.front(), -5);
    ASSERT_EQ(std::vector<int>(shared.begin() + 1, shared.end()), fresh) << "round " << round;
    ASSERT_TRUE(std::is_sorted(fresh.begin(), fresh.end()));
    for (std::size_t t = 0; t < g.tris.size(); ++t) {
      if (overlaps(qlo, qhi, g.lo[t], g.hi[t])) {
        ASSERT_TRUE(std::binary_search(fresh.begin(), fresh.end(), int(t))) << "round " << round << ", triangle " << t;
      }
    }
    ASSERT_GE(marks.size(), (g.tris.size() + 63) / 64);
    for (const std::uint64_t w : marks) ASSERT_EQ(w, 0u) << "round " << round;
    nonempty += fresh.empty() ? 0 : 1;
  }
  EXPECT_GT(nonempty, 200);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
