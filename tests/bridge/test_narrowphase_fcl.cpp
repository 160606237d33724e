// Regression tests for the FCL 0.7 behaviour the bridge avoids (docs/design.md
// section 4, docs/collision-queries.md). Each test calls FCL (Debian's
// libfcl 0.7.0, double) on a configuration with a known closed-form answer,
// asserts that FCL deviates from it as observed, and that the bridge's query
// gives the right answer. If an FCL upgrade fixes a problem, the FCL half of
// its test fails: then revisit the table in docs/collision-queries.md.
// Only calls that do not reach FCL's assertions are made (Debian builds FCL
// with assertions on); the half-space crash runs in a death test.
#include <gtest/gtest.h>

#include <btBulletCollisionCommon.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/sphere_capsule.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/sphere_triangle.h>
#include <fcl/narrowphase/distance.h>

#include <memory>

#include "test_narrowphase_util.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace np_test;
using xpbd_bullet::ParticleContact;
using xpbd_bullet::query_point;

namespace {

// FCL signed distance (libccd GJK/EPA, the default solver) between a sphere of
// radius r at c and `shape` at the origin; returns the distance and the
// witness point on `shape`.
template <class Shape>
double fcl_signed_distance(std::shared_ptr<Shape> shape, const Eigen::Vector3d& c, double r,
                           Eigen::Vector3d* on_shape = nullptr) {
  fcl::Transform3d tc = fcl::Transform3d::Identity();
  tc.translation() = c;
  fcl::CollisionObjectd a(std::make_shared<fcl::Sphered>(r), tc), b(shape, fcl::Transform3d::Identity());
  fcl::DistanceRequestd req;
  req.enable_signed_distance = true;
  req.enable_nearest_points = true;
  fcl::DistanceResultd res;
  fcl::distance(&a, &b, req, res);
  if (on_shape) *on_shape = res.nearest_points[1];
  return res.min_distance;
}

ParticleContact bridge_query(btCollisionShape& shape, const D3& x) {
  auto obj = make_object(&shape, Pose{});
  ParticleContact c;
  EXPECT_TRUE(query_point(*obj, vec(x), Real(10), c));
  return c;
}

// Tolerance of the bridge's closed forms here (coordinates ~1 m).
constexpr double kTol = 64 * kEps;

}  // namespace

// fcl PR #569 (never merged): sphereTriangleIntersect reports a NEGATIVE
// penetration depth and a normal that flips with the side of the triangle,
// so a particle slightly behind a one-sided ground is pushed further through.
TEST(NarrowphaseFcl, SphereTriangleHasNegativeDepthAndTwoSidedNormals) {
  // Triangle in y = 0, counter-clockwise seen from +y: face normal +y.
  const Eigen::Vector3d P1(-1, 0, -1), P2(-1, 0, 2), P3(2, 0, -1);
  ASSERT_GT((P2 - P1).cross(P3 - P1).y(), 0);
  const double radius = 0.1;  // the particle
  double depth_front = 0, depth_back = 0;
  Eigen::Vector3d n_front, n_back, cp;
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = Eigen::Vector3d(0.25, 0.05, 0.25);  // centre 0.05 in front
  ASSERT_TRUE(fcl::detail::sphereTriangleIntersect(fcl::Sphered(radius), tf, P1, P2, P3, &cp, &depth_front, &n_front));
  tf.translation() = Eigen::Vector3d(0.25, -0.05, 0.25);  // centre 0.05 behind
  ASSERT_TRUE(fcl::detail::sphereTriangleIntersect(fcl::Sphered(radius), tf, P1, P2, P3, &cp, &depth_back, &n_back));
  // Observed (FCL 0.7.0): depth -0.05 on both sides (true overlap: +0.05 in
  // front, +0.15 behind a one-sided surface); normal (0, -1, 0) in front and
  // (0, +1, 0) behind: it follows the side of the centre, not the face.
  EXPECT_NEAR(depth_front, -0.05, 1e-12);
  EXPECT_NEAR(depth_back, -0.05, 1e-12);
  EXPECT_NEAR(n_front.y(), -1, 1e-12);
  EXPECT_NEAR(n_back.y(), 1, 1e-12);

  // The bridge: one-sided, signed centre distance, the face normal on both sides.
  btTriangleMesh mesh;
  mesh.addTriangle(btVector3(-1, 0, -1), btVector3(-1, 0, 2), btVector3(2, 0, -1));
  btBvhTriangleMeshShape shape(&mesh, true);
  ParticleContact c = bridge_query(shape, D3(0.25, 0.05, 0.25));
  EXPECT_NEAR(c.distance, 0.05, kTol);  // overlap = radius - distance = 0.05
  EXPECT_NEAR(c.normal.y(), 1, kTol);
  c = bridge_query(shape, D3(0.25, -0.05, 0.25));
  EXPECT_NEAR(c.distance, -0.05, kTol);  // overlap = 0.15: behind the surface
  EXPECT_NEAR(c.normal.y(), 1, kTol);   // pushed back out the front
}

// sphereCapsuleIntersect normalises centre - axis point; on the axis that is a
// zero vector and the contact normal comes out (0, 0, 0).
TEST(NarrowphaseFcl, SphereCapsuleContactHasNoNormalOnTheAxis) {
  const fcl::Capsuled capsule(0.5, 2.0);  // radius 0.5, length 2 along z
  fcl::Transform3d ts = fcl::Transform3d::Identity();
  ts.translation() = Eigen::Vector3d(0, 0, 0.5);
  std::vector<fcl::ContactPointd> contacts;
  ASSERT_TRUE(fcl::detail::sphereCapsuleIntersect(fcl::Sphered(0.01), ts, capsule, fcl::Transform3d::Identity(),
                                                  &contacts));
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].normal.norm(), 0) << "observed: zero normal";
  EXPECT_NEAR(contacts[0].penetration_depth, 0.51, 1e-12);

  btCapsuleShapeZ shape(0.5, 2.0);
  const ParticleContact c = bridge_query(shape, D3(0, 0, 0.5));
  EXPECT_NEAR(c.distance, -0.5, kTol);
  EXPECT_NEAR(d3(c.normal).norm(), 1, kTol);
  EXPECT_NEAR(c.normal.z(), 0, kTol);
}

// With enable_signed_distance FCL runs libccd's GJK/EPA for every primitive
// pair (its closed-form sphere-box/capsule/cylinder distances are only used
// unsigned). A zero-radius sphere (a point) outside a box gets a vertex instead
// of the nearest face.
TEST(NarrowphaseFcl, SignedDistanceOfAPointOutsideABoxPicksAVertex) {
  Eigen::Vector3d w;
  const double d = fcl_signed_distance(std::make_shared<fcl::Boxd>(2, 1, 0.5), Eigen::Vector3d(1.5, 0, 0), 0, &w);
  // Observed: 0.75 to the vertex (1, -0.5, -0.25); exact: 0.5 to the face x = 1.
  EXPECT_NEAR(d, 0.75, 1e-6);
  EXPECT_NEAR((w - Eigen::Vector3d(1, -0.5, -0.25)).norm(), 0, 1e-6);

  btBoxShape shape(btVector3(1, 0.5, 0.25));
  const ParticleContact c = bridge_query(shape, D3(1.5, 0, 0));
  EXPECT_NEAR(c.distance, 0.5, kTol);
  EXPECT_NEAR((d3(c.point) - D3(1, 0, 0)).norm(), 0, kTol);
}

// libccd's GJK on curved shapes stops early: outside a capsule the distance of
// a point is off by 6 mm (worst of 20000 random points; typical 1e-3 m).
TEST(NarrowphaseFcl, SignedDistanceOutsideACapsuleIsApproximate) {
  const Eigen::Vector3d x(-0.94793369581393594, -0.14439102103782187, 1.2619114381880205);
  const double exact = (x - Eigen::Vector3d(0, 0, 1)).norm() - 0.5;  // nearest: the top sphere, centre (0, 0, 1)
  const double d = fcl_signed_distance(std::make_shared<fcl::Capsuled>(0.5, 2.0), x, 0);
  EXPECT_GT(std::abs(d - exact), 1e-3) << "observed 0.500006 vs exact " << exact;

  btCapsuleShapeZ shape(0.5, 2.0);
  EXPECT_NEAR(bridge_query(shape, x).distance, exact, kTol);
}

// Inside a cylinder EPA's depth is good to 1e-6 m, but its witness point (and
// so the normal) is off by 0.3 mm; the exact nearest point is on the barrel.
TEST(NarrowphaseFcl, SignedDistanceInsideACylinderHasAnOffWitness) {
  const Eigen::Vector3d x(0.3, 0, 0.2);
  Eigen::Vector3d w;
  const double d = fcl_signed_distance(std::make_shared<fcl::Cylinderd>(0.5, 2.0), x, 0, &w);
  EXPECT_NEAR(d, -0.2, 1e-5);
  EXPECT_GT((w - Eigen::Vector3d(0.5, 0, 0.2)).norm(), 1e-4) << "observed witness " << w.transpose();

  btCylinderShapeZ shape(btVector3(0.5, 0.5, 1.0));
  const ParticleContact c = bridge_query(shape, D3(0.3, 0, 0.2));
  EXPECT_NEAR(c.distance, -0.2, kTol);
  EXPECT_NEAR((d3(c.point) - D3(0.5, 0, 0.2)).norm(), 0, kTol);
  EXPECT_NEAR((d3(c.normal) - D3::UnitX()).norm(), 0, kTol);
}

// Signed distance against a half-space: libccd is handed a null support
// function and the process dies (SIGSEGV). The bridge's plane is a closed form.
TEST(NarrowphaseFclDeathTest, SignedDistanceAgainstAHalfspaceCrashes) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(fcl_signed_distance(std::make_shared<fcl::Halfspaced>(Eigen::Vector3d(0, 1, 0), 0.0),
                                   Eigen::Vector3d(0.3, 0.5, 0.2), 1e-3),
               "");

  btStaticPlaneShape shape(btVector3(0, 1, 0), 0);
  EXPECT_NEAR(bridge_query(shape, D3(0.3, 0.5, 0.2)).distance, 0.5, kTol);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
