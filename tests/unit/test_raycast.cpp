// Ray queries against a system's visible surface (xpbd/raycast.hpp), against
// closed forms: a flat cloth grid, where the triangle and the barycentric
// weights of a hit follow from the grid's layout (builders.hpp); two
// parallel cloths; a tet box, entered and left through two faces; and the
// cases that never hit.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "xpbd/builders.hpp"
#include "xpbd/compile.hpp"
#include "xpbd/error.hpp"
#include "xpbd/raycast.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;

// Round-off of the float build at coordinates of order 1.
constexpr Real kTol = std::numeric_limits<Real>::epsilon() * 64;

// A 5 x 5 cloth of 1 m lying in the plane y = h: particle (i, j) at
// (0.25 i, h, 0.25 j). Its normal u x v = x cross z = -y.
xpbd::ClothGrid flat_cloth(xpbd::SceneDesc& scene, Real h) {
  xpbd::ClothGridDesc d;
  d.nx = d.ny = 5;
  d.origin = Vec3(0, h, 0);
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  return xpbd::add_cloth_grid(scene, d);
}

TEST(Raycast, HitOnAFlatClothHasTheGridsTriangleAndWeights) {
  xpbd::SceneDesc scene;
  const xpbd::ClothGrid g = flat_cloth(scene, 0);
  const xpbd::Model m = xpbd::compile(scene);
  const xpbd::State s = xpbd::make_state(m);
  ASSERT_EQ(m.surface_triangles.size(), 32u);  // 4 x 4 quads, two triangles each

  // Straight down through (0.3, 0, 0.6): quad (1, 2), local (s, t) = (0.2,
  // 0.4). t > s: the triangle ((i,j), (i+1,j+1), (i,j+1)), the quad's second,
  // index 2 (j (nx-1) + i) + 1 = 19; the point is w1 (1, 1) + w2 (0, 1) in
  // the quad's units, so w1 = s = 0.2, w2 = t - s = 0.2, w0 = 0.6.
  const auto h = xpbd::ray_closest(m, s, Vec3(Real(0.3), 1, Real(0.6)), Vec3(Real(0.3), -1, Real(0.6)));
  ASSERT_TRUE(h.has_value());
  EXPECT_EQ(h->triangle, 19u);
  const std::array<Index, 3> expect{g.at(1, 2), g.at(2, 3), g.at(1, 3)};
  EXPECT_EQ(h->particles, expect);
  EXPECT_NEAR(h->barycentric[0], 0.6, kTol);
  EXPECT_NEAR(h->barycentric[1], 0.2, kTol);
  EXPECT_NEAR(h->barycentric[2], 0.2, kTol);
  EXPECT_NEAR(h->fraction, 0.5, kTol);
  EXPECT_NEAR(h->distance, 1.0, kTol);
  EXPECT_NEAR((h->point - Vec3(Real(0.3), 0, Real(0.6))).norm(), 0, kTol);
  // The grid's normal is -y; the ray comes from above, so the hit normal is +y.
  EXPECT_NEAR((h->normal - Vec3::UnitY()).norm(), 0, kTol);

  // From below the same point: the same triangle, the normal now -y.
  const auto below = xpbd::ray_closest(m, s, Vec3(Real(0.3), -2, Real(0.6)), Vec3(Real(0.3), 2, Real(0.6)));
  ASSERT_TRUE(below.has_value());
  EXPECT_EQ(below->triangle, 19u);
  EXPECT_NEAR(below->fraction, 0.5, kTol);
  EXPECT_NEAR(below->distance, 2.0, kTol);
  EXPECT_NEAR((below->normal + Vec3::UnitY()).norm(), 0, kTol);

  // A slanted ray: from (0, 1, 0) to (1, -1, 1) crosses y = 0 half way, at
  // (0.5, 0, 0.5), the shared corner of quads (1,1), (2,1), (1,2), (2,2):
  // every triangle touching it that contains it is hit at the same fraction.
  const auto all = xpbd::ray_hits(m, s, Vec3(0, 1, 0), Vec3(1, -1, 1));
  ASSERT_FALSE(all.empty());
  for (const auto& x : all) {
    EXPECT_NEAR(x.fraction, 0.5, kTol);
    EXPECT_NEAR((x.point - Vec3(Real(0.5), 0, Real(0.5))).norm(), 0, kTol);
  }
  for (std::size_t k = 1; k < all.size(); ++k) EXPECT_LT(all[k - 1].triangle, all[k].triangle);
}

TEST(Raycast, AllHitsAreNearestFirstAcrossLayers) {
  xpbd::SceneDesc scene;
  flat_cloth(scene, 0);
  const xpbd::ClothGrid upper = flat_cloth(scene, Real(0.5));
  const xpbd::Model m = xpbd::compile(scene);
  const xpbd::State s = xpbd::make_state(m);
  // Down from y = 1 to y = -1 at (0.6, ., 0.3): the upper cloth at 1/4 of
  // the way, the lower at 1/2.
  const auto hits = xpbd::ray_hits(m, s, Vec3(Real(0.6), 1, Real(0.3)), Vec3(Real(0.6), -1, Real(0.3)));
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_NEAR(hits[0].fraction, 0.25, kTol);
  EXPECT_NEAR(hits[1].fraction, 0.5, kTol);
  EXPECT_GE(hits[0].particles[0], upper.first);
  EXPECT_LT(hits[1].particles[0], upper.first);
  // A segment that stops between the layers hits the upper one only.
  EXPECT_EQ(xpbd::ray_hits(m, s, Vec3(Real(0.6), 1, Real(0.3)), Vec3(Real(0.6), Real(0.2), Real(0.3))).size(), 1u);
}

TEST(Raycast, TetBoxIsEnteredAndLeftThroughItsBoundary) {
  xpbd::SceneDesc scene;
  xpbd::TetBoxDesc d;
  d.nx = d.ny = d.nz = 2;
  d.origin = Vec3(0, 0, 0);
  d.size = Vec3(1, 1, 1);
  const xpbd::TetBox b = xpbd::add_tet_box(scene, d);
  const xpbd::Model m = xpbd::compile(scene);
  const xpbd::State s = xpbd::make_state(m);
  EXPECT_EQ(m.surface_triangles.size(), b.surface.size());
  // Along x through (., 0.3, 0.7), from x = -1 to x = 3: enters at x = 0
  // (fraction 1/4) and leaves at x = 1 (fraction 1/2), hitting no inner face.
  const auto hits = xpbd::ray_hits(m, s, Vec3(-1, Real(0.3), Real(0.7)), Vec3(3, Real(0.3), Real(0.7)));
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_NEAR(hits[0].fraction, 0.25, kTol);
  EXPECT_NEAR((hits[0].normal + Vec3::UnitX()).norm(), 0, kTol);
  EXPECT_NEAR(hits[1].fraction, 0.5, kTol);
  EXPECT_NEAR((hits[1].normal + Vec3::UnitX()).norm(), 0, kTol);  // facing `from` too
}

TEST(Raycast, MissesAndBadInput) {
  xpbd::SceneDesc scene;
  flat_cloth(scene, 0);
  xpbd::RopeDesc r;
  r.n = 5;
  r.start = Vec3(0, 1, 0);
  r.dir = Vec3::UnitX();
  r.spacing = Real(0.25);
  xpbd::add_rope(scene, r);  // no surface: never hit
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  // Beside the cloth, short of it, along its plane, of zero length, along the rope.
  EXPECT_FALSE(xpbd::ray_closest(m, s, Vec3(2, 1, Real(0.5)), Vec3(2, -1, Real(0.5))));
  EXPECT_FALSE(xpbd::ray_closest(m, s, Vec3(Real(0.5), 1, Real(0.5)), Vec3(Real(0.5), Real(0.1), Real(0.5))));
  EXPECT_FALSE(xpbd::ray_closest(m, s, Vec3(-1, 0, Real(0.5)), Vec3(2, 0, Real(0.5))));
  EXPECT_FALSE(xpbd::ray_closest(m, s, Vec3(Real(0.5), 0, Real(0.5)), Vec3(Real(0.5), 0, Real(0.5))));
  EXPECT_FALSE(xpbd::ray_closest(m, s, Vec3(Real(0.5), 2, 0), Vec3(Real(0.5), Real(0.5), 0)));
  // A triangle with a particle that is not finite is never hit; the others are.
  s.x[0] = Vec3::Constant(std::numeric_limits<Real>::quiet_NaN());
  EXPECT_FALSE(xpbd::ray_closest(m, s, Vec3(Real(0.05), 1, Real(0.1)), Vec3(Real(0.05), -1, Real(0.1))));
  EXPECT_TRUE(xpbd::ray_closest(m, s, Vec3(Real(0.6), 1, Real(0.6)), Vec3(Real(0.6), -1, Real(0.6))));
  // Bad input is named.
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  try {
    xpbd::ray_hits(m, s, Vec3(0, nan, 0), Vec3::Zero());
    FAIL() << "no exception";
  } catch (const xpbd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("from"), std::string::npos) << e.what();
  }
  try {
    xpbd::ray_hits(m, xpbd::State{}, Vec3::Zero(), Vec3::UnitY());
    FAIL() << "no exception";
  } catch (const xpbd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("particles"), std::string::npos) << e.what();
  }
}

TEST(Raycast, SurfaceTrianglesAreCheckedByCompile) {
  xpbd::SceneDesc scene;
  flat_cloth(scene, 0);
  scene.surface_triangles.push_back({0, 1, 99});
  try {
    xpbd::compile(scene);
    FAIL() << "no exception";
  } catch (const xpbd::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("surface_triangles[32]"), std::string::npos) << e.what();
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
