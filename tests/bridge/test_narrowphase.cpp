// Known-answer tests of query_point (particle centre vs rigid shape signed
// distance), docs/design.md section 4. Every expected value is a closed form written
// in the test or an independent reference formula from test_narrowphase_util.hpp.
//
// Tolerances: the closed forms do O(10) floating-point operations on
// coordinates of at most a few metres, so their round-off is a few
// eps * |x|; kTol = 256 eps * (1 + |x|) leaves a margin of ~10 (double: ~6e-14 m).
// Normals n = (x - point) / |d| carry that error divided by |d|, so normal
// checks use points with |d| >= 1e-3 m and a tolerance of kTol / |d| plus the
// 1e-7 error of the finite-difference reference.
#include <gtest/gtest.h>

#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <BulletCollision/CollisionShapes/btEmptyShape.h>
#include <btBulletCollisionCommon.h>

#include <functional>
#include <stdexcept>
#include <string>

#include "test_narrowphase_util.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace np_test;
using xpbd_bullet::ParticleContact;
using xpbd_bullet::query_point;

namespace {

double tol_at(const D3& x) { return 256 * kEps * (1 + x.cwiseAbs().maxCoeff()); }

// Checks one query against the reference sdf (local frame of `pose`): the
// distance, the contact point on the surface (|sdf(point)| ~ 0), the identity
// x = point + d n, and the normal against the reference gradient where the
// nearest feature is unique. Returns false (with a message) on mismatch.
::testing::AssertionResult matches(const btCollisionObject& obj, const Pose& pose,
                                   const std::function<double(const D3&)>& sdf, const D3& x,
                                   double tol_scale = 1) {
  ParticleContact c;
  const double tol = tol_scale * tol_at(x);
  if (!query_point(obj, vec(x), Real(1e3), c)) return ::testing::AssertionFailure() << "no contact at " << x.transpose();
  const D3 p = pose.to_local(x);
  const double d_ref = sdf(p);
  if (std::abs(c.distance - d_ref) > tol)
    return ::testing::AssertionFailure() << "x=" << x.transpose() << " d=" << c.distance << " ref " << d_ref;
  if (std::abs(sdf(pose.to_local(d3(c.point)))) > tol)
    return ::testing::AssertionFailure() << "x=" << x.transpose() << " point " << c.point.transpose()
                                         << " is not on the surface: sdf " << sdf(pose.to_local(d3(c.point)));
  if (std::abs(d3(c.normal).norm() - 1) > tol)
    return ::testing::AssertionFailure() << "normal not unit: " << c.normal.transpose();
  if ((d3(c.point) + c.distance * d3(c.normal) - x).norm() > 2 * tol)
    return ::testing::AssertionFailure() << "x != point + d n at x=" << x.transpose();
  D3 n_local;
  if (std::abs(d_ref) >= 1e-3 && ref_normal(sdf, p, n_local)) {
    const D3 n_ref = pose.R * n_local;
    if ((d3(c.normal) - n_ref).norm() > tol / std::abs(d_ref) + 1e-7)
      return ::testing::AssertionFailure() << "x=" << x.transpose() << " normal " << c.normal.transpose()
                                           << " ref " << n_ref.transpose();
  }
  return ::testing::AssertionSuccess();
}

// Random points in a box of half size `ext` around the pose's origin.
std::vector<D3> random_points(const Pose& pose, double ext, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-ext, ext);
  std::vector<D3> pts;
  for (int i = 0; i < n; ++i) pts.push_back(pose.to_world(D3(u(rng), u(rng), u(rng))));
  return pts;
}

const Pose kPose = make_pose(D3(1, 2, -0.5), 0.7, D3(0.3, -1.2, 2.5));  // an arbitrary rigid motion

ParticleContact query(const btCollisionObject& obj, const D3& x, double max_d = 1e3) {
  ParticleContact c;
  EXPECT_TRUE(query_point(obj, vec(x), Real(max_d), c)) << "x=" << x.transpose();
  return c;
}

void expect_vec(const Vec3& got, const D3& want, double tol, const char* what) {
  EXPECT_LE((d3(got) - want).norm(), tol) << what << ": got " << got.transpose() << ", want " << want.transpose();
}

}  // namespace

// ---------------------------------------------------------------- sphere
TEST(NarrowphaseSphere, OutsideInsideAndCentre) {
  btSphereShape shape(0.5);
  const Pose pose = make_pose(D3::UnitX(), 0, D3(1, 2, 3));
  auto obj = make_object(&shape, pose);
  // Outside along +x: d = 0.8 - 0.5.
  ParticleContact c = query(*obj, D3(1.8, 2, 3));
  EXPECT_NEAR(c.distance, 0.3, kT);
  expect_vec(c.normal, D3::UnitX(), kT, "normal");
  expect_vec(c.point, D3(1.5, 2, 3), kT, "point");
  // Inside, 0.1 below the centre: depth 0.4, normal -y, point on the bottom.
  c = query(*obj, D3(1, 1.9, 3));
  EXPECT_NEAR(c.distance, -0.4, kT);
  expect_vec(c.normal, -D3::UnitY(), kT, "normal");
  expect_vec(c.point, D3(1, 1.5, 3), kT, "point");
  // At the centre every direction is nearest: depth = radius, unit normal.
  c = query(*obj, D3(1, 2, 3));
  EXPECT_NEAR(c.distance, -0.5, kT);
  EXPECT_NEAR(d3(c.normal).norm(), 1, kT);
  EXPECT_NEAR((d3(c.point) - D3(1, 2, 3)).norm(), 0.5, kT);
}

// ---------------------------------------------------------------- box
TEST(NarrowphaseBox, FaceEdgeCornerAndInside) {
  btBoxShape shape(btVector3(1, 0.5, 0.25));
  auto obj = make_object(&shape, Pose{});
  // Face region above +z: d = 0.5 - 0.25.
  ParticleContact c = query(*obj, D3(0.2, 0.1, 0.5));
  EXPECT_NEAR(c.distance, 0.25, kT);
  expect_vec(c.normal, D3::UnitZ(), kT, "face normal");
  expect_vec(c.point, D3(0.2, 0.1, 0.25), kT, "face point");
  // Edge region (x, y outside): offset (0.3, 0.4, 0) from the edge, d = 0.5.
  c = query(*obj, D3(1.3, 0.9, 0.1));
  EXPECT_NEAR(c.distance, 0.5, kT);
  expect_vec(c.normal, D3(0.6, 0.8, 0), kT, "edge normal");
  expect_vec(c.point, D3(1, 0.5, 0.1), kT, "edge point");
  // Corner region: offset (0.3, 0.4, 1.2) from the corner, d = 1.3 (3-4-12-13).
  c = query(*obj, D3(1.3, 0.9, 1.45));
  EXPECT_NEAR(c.distance, 1.3, kT);
  expect_vec(c.normal, D3(3, 4, 12) / 13, kT, "corner normal");
  expect_vec(c.point, D3(1, 0.5, 0.25), kT, "corner point");
  // Inside: the face distances are x 0.7, y 0.4, z 0.2, so the +z face is
  // nearest: depth 0.2, normal +z, point straight above.
  c = query(*obj, D3(0.3, 0.1, 0.05));
  EXPECT_NEAR(c.distance, -0.2, kT);
  expect_vec(c.normal, D3::UnitZ(), 0, "inside normal");
  expect_vec(c.point, D3(0.3, 0.1, 0.25), kT, "inside point");
  // Inside near the -x face: depth 0.1, normal -x.
  c = query(*obj, D3(-0.9, 0, 0));
  EXPECT_NEAR(c.distance, -0.1, kT);
  expect_vec(c.normal, -D3::UnitX(), 0, "inside normal -x");
}

TEST(NarrowphaseBox, LocalScalingIsApplied) {
  // Bullet scales the half extents: (1, 0.5, 0.25) scaled by (2, 1, 4) = (2, 0.5, 1).
  btBoxShape shape(btVector3(1, 0.5, 0.25));
  shape.setLocalScaling(btVector3(2, 1, 4));
  auto obj = make_object(&shape, Pose{});
  EXPECT_NEAR(query(*obj, D3(3, 0, 0)).distance, 1, kT);
  EXPECT_NEAR(query(*obj, D3(0, 0, 1.5)).distance, 0.5, kT);
  EXPECT_NEAR(query(*obj, D3(0, 0, 0)).distance, -0.5, kT);
}

// ---------------------------------------------------------------- capsule
TEST(NarrowphaseCapsule, AllThreeAxisVariants) {
  // radius 0.3, cylinder height 1 (half height 0.5), along X, Y, Z.
  btCapsuleShapeX cx(0.3, 1.0);
  btCapsuleShape cy(0.3, 1.0);
  btCapsuleShapeZ cz(0.3, 1.0);
  btCapsuleShape* shapes[3] = {&cx, &cy, &cz};
  for (int up = 0; up < 3; ++up) {
    SCOPED_TRACE("up axis " + std::to_string(up));
    auto obj = make_object(shapes[up], Pose{});
    const D3 e = D3::Unit(up), r = D3::Unit((up + 2) % 3);
    // Beyond the end cap on the axis: 1.0 - 0.5 - 0.3.
    ParticleContact c = query(*obj, 1.0 * e);
    EXPECT_NEAR(c.distance, 0.2, kT);
    expect_vec(c.normal, e, kT, "cap normal");
    expect_vec(c.point, 0.8 * e, kT, "cap point");
    // Beside the barrel: radial 0.5, axial -0.2: 0.5 - 0.3.
    c = query(*obj, 0.5 * r - 0.2 * e);
    EXPECT_NEAR(c.distance, 0.2, kT);
    expect_vec(c.normal, r, kT, "barrel normal");
    expect_vec(c.point, 0.3 * r - 0.2 * e, kT, "barrel point");
    // Inside off the axis: radial 0.1, depth 0.2, normal radial.
    c = query(*obj, 0.1 * r + 0.4 * e);
    EXPECT_NEAR(c.distance, -0.2, kT);
    expect_vec(c.normal, r, kT, "inside normal");
    // On the axis: depth = radius, the normal is some unit radial direction.
    c = query(*obj, 0.1 * e);
    EXPECT_NEAR(c.distance, -0.3, kT);
    EXPECT_NEAR(d3(c.normal).norm(), 1, kT);
    EXPECT_NEAR(d3(c.normal).dot(e), 0, kT);
  }
}

// ---------------------------------------------------------------- cylinder
TEST(NarrowphaseCylinder, AllThreeAxisVariants) {
  // radius 0.4, half height 0.6, along X, Y, Z (Bullet takes half extents).
  btCylinderShapeX cx(btVector3(0.6, 0.4, 0.4));
  btCylinderShape cy(btVector3(0.4, 0.6, 0.4));
  btCylinderShapeZ cz(btVector3(0.4, 0.4, 0.6));
  btCylinderShape* shapes[3] = {&cx, &cy, &cz};
  for (int up = 0; up < 3; ++up) {
    SCOPED_TRACE("up axis " + std::to_string(up));
    auto obj = make_object(shapes[up], Pose{});
    const D3 e = D3::Unit(up), r = D3::Unit((up + 1) % 3);
    ParticleContact c = query(*obj, 1.0 * e);  // above the cap: 1.0 - 0.6
    EXPECT_NEAR(c.distance, 0.4, kT);
    expect_vec(c.normal, e, kT, "cap normal");
    c = query(*obj, 0.7 * r + 0.1 * e);  // beside the barrel: 0.7 - 0.4
    EXPECT_NEAR(c.distance, 0.3, kT);
    expect_vec(c.normal, r, kT, "barrel normal");
    expect_vec(c.point, 0.4 * r + 0.1 * e, kT, "barrel point");
    c = query(*obj, 0.7 * r - 1.0 * e);  // off the rim by (0.3, 0.4): 0.5
    EXPECT_NEAR(c.distance, 0.5, kT);
    expect_vec(c.normal, 0.6 * r - 0.8 * e, kT, "rim normal");
    expect_vec(c.point, 0.4 * r - 0.6 * e, kT, "rim point");
    c = query(*obj, 0.3 * r);  // inside, nearer the barrel (0.1) than a cap (0.6)
    EXPECT_NEAR(c.distance, -0.1, kT);
    expect_vec(c.normal, r, kT, "inside barrel normal");
    c = query(*obj, 0.5 * e);  // inside on the axis, nearer the cap (0.1) than the barrel (0.4)
    EXPECT_NEAR(c.distance, -0.1, kT);
    expect_vec(c.normal, e, 0, "inside cap normal");
    expect_vec(c.point, 0.6 * e, kT, "inside cap point");
  }
}

// ---------------------------------------------------------------- plane
TEST(NarrowphasePlane, HalfSpaceBelowThePlane) {
  // Local plane y = 0.5 (normal +y); the object is turned 90 degrees about z,
  // so the world normal is R e_y = -x and the plane is x = -0.5 + t.x.
  btStaticPlaneShape shape(btVector3(0, 1, 0), 0.5);
  const Pose pose = make_pose(D3::UnitZ(), M_PI / 2, D3(2, 0, 0));
  auto obj = make_object(&shape, pose);
  ParticleContact c = query(*obj, D3(1.2, 7, -3));  // 0.3 on the normal side
  EXPECT_NEAR(c.distance, 0.3, kT);
  expect_vec(c.normal, -D3::UnitX(), kT, "normal");
  expect_vec(c.point, D3(1.5, 7, -3), kT, "point");
  c = query(*obj, D3(1.7, 0, 0));  // 0.2 behind it
  EXPECT_NEAR(c.distance, -0.2, kT);
  expect_vec(c.normal, -D3::UnitX(), kT, "normal behind");
}

// ------------------------------------------ random points vs independent references
TEST(NarrowphaseRandom, PrimitivesMatchIndependentReferencesUnderRigidMotion) {
  btSphereShape sphere(0.7);
  btBoxShape box(btVector3(1, 0.5, 0.25));
  btCapsuleShapeX capx(0.3, 1.2);
  btCapsuleShape capy(0.3, 1.2);
  btCapsuleShapeZ capz(0.3, 1.2);
  btCylinderShapeX cylx(btVector3(0.6, 0.4, 0.4));
  btCylinderShape cyly(btVector3(0.4, 0.6, 0.4));
  btCylinderShapeZ cylz(btVector3(0.4, 0.4, 0.6));
  btStaticPlaneShape plane(btVector3(1, 2, 2), 0.3);  // Bullet normalises: n = (1, 2, 2) / 3
  struct Case {
    const char* name;
    btCollisionShape* shape;
    std::function<double(const D3&)> sdf;
  };
  const Case cases[] = {
      {"sphere", &sphere, [](const D3& p) { return ref_sphere(0.7, p); }},
      {"box", &box, [](const D3& p) { return ref_box(D3(1, 0.5, 0.25), p); }},
      {"capsule X", &capx, [](const D3& p) { return ref_capsule(0, 0.3, 0.6, p); }},
      {"capsule Y", &capy, [](const D3& p) { return ref_capsule(1, 0.3, 0.6, p); }},
      {"capsule Z", &capz, [](const D3& p) { return ref_capsule(2, 0.3, 0.6, p); }},
      {"cylinder X", &cylx, [](const D3& p) { return ref_cylinder(0, 0.4, 0.6, p); }},
      {"cylinder Y", &cyly, [](const D3& p) { return ref_cylinder(1, 0.4, 0.6, p); }},
      {"cylinder Z", &cylz, [](const D3& p) { return ref_cylinder(2, 0.4, 0.6, p); }},
      {"plane", &plane, [](const D3& p) { return p.dot(D3(1, 2, 2) / 3) - 0.3; }},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.name);
    auto obj = make_object(k.shape, kPose);
    int inside = 0, failures = 0;
    for (const D3& x : random_points(kPose, 1.5, 3000, 11)) {
      const auto r = matches(*obj, kPose, k.sdf, x);
      if (!r && ++failures <= 5) ADD_FAILURE() << r.message();
      inside += k.sdf(kPose.to_local(x)) < 0;
    }
    EXPECT_EQ(failures, 0);
    EXPECT_GT(inside, 30) << "the sample must cover the inside too";
  }
}

// ---------------------------------------------------------------- convex hull (GJK/EPA)
// Bullet's GJK/EPA in double stops at 1e-12 (GJK_ACCURACY, EPA_ACCURACY); the
// distances it returns for the cube hull agree with the box to ~3e-13 m
// (measured), so 1e-9 m is a safe bound. Bullet's float GJK (GJK_ACCURACY
// 1e-4) was measured off by up to 4e-3 m at 0.35 m from a rotated hull.
constexpr double kGjkTol = std::is_same_v<Real, double> ? 1e-9 : 1e-2;

TEST(NarrowphaseConvexHull, CubeHullWithoutMarginIsTheBox) {
  const D3 h(0.5, 0.3, 0.2);
  btConvexHullShape hull;
  for (int i = 0; i < 8; ++i) hull.addPoint(btVector3(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z()));
  hull.setMargin(0);  // explicit: Bullet's default margin is 0.04 m
  auto obj = make_object(&hull, kPose);
  auto sdf = [&](const D3& p) { return ref_box(h, p); };
  int failures = 0;
  for (const D3& x : random_points(kPose, 1.0, 2000, 5)) {
    const auto r = matches(*obj, kPose, sdf, x, kGjkTol / tol_at(x));
    if (!r && ++failures <= 5) ADD_FAILURE() << r.message();
  }
  EXPECT_EQ(failures, 0);
  // A point exactly on a face: distance 0 and the outward face normal (Bullet
  // 3.24's SignedDistance returns an inward normal there; the bridge flips it).
  ParticleContact c = query(*obj, kPose.to_world(D3(0.5, 0.1, 0.05)));
  EXPECT_NEAR(c.distance, 0, kGjkTol);
  expect_vec(c.normal, kPose.R * D3::UnitX(), kGjkTol, "normal on the face");
}

TEST(NarrowphaseConvexHull, MarginGrowsTheHull) {
  // With margin m Bullet's surface is the hull grown by m (Minkowski sum with
  // a sphere), whose signed distance is exactly the box's minus m, inside and out.
  const D3 h(0.5, 0.3, 0.2);
  const double m = 0.05;
  btConvexHullShape hull;
  for (int i = 0; i < 8; ++i) hull.addPoint(btVector3(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z()));
  hull.setMargin(m);
  auto obj = make_object(&hull, kPose);
  auto sdf = [&](const D3& p) { return ref_box(h, p) - m; };
  int failures = 0;
  for (const D3& x : random_points(kPose, 1.0, 2000, 6)) {
    const auto r = matches(*obj, kPose, sdf, x, kGjkTol / tol_at(x));
    if (!r && ++failures <= 5) ADD_FAILURE() << r.message();
  }
  EXPECT_EQ(failures, 0);
  // On the core hull's face (inside the margin band by m): GJK has no
  // direction there, the EPA fallback answers: depth m, normal +x.
  ParticleContact c = query(*obj, kPose.to_world(D3(0.5, 0.1, 0.05)));
  EXPECT_NEAR(c.distance, -m, kGjkTol);
  expect_vec(c.normal, kPose.R * D3::UnitX(), kGjkTol, "normal on the core face");
}

TEST(NarrowphaseConvexHull, NormalIsTheFaceNormalRightAtTheSurface) {
  // A resting particle sits within round-off of the surface. GJK's normal
  // there, (x - w) / |x - w|, would carry the witness error (~1e-12 m) divided
  // by the distance; the bridge takes EPA's face plane instead (and orients it
  // outward), so the normal is the face normal at any distance from it.
  const D3 h(0.5, 0.3, 0.2);
  for (double m : {0.0, 0.04}) {
    SCOPED_TRACE("margin " + std::to_string(m));
    btConvexHullShape hull;
    for (int i = 0; i < 8; ++i) hull.addPoint(btVector3(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z()));
    hull.setMargin(m);
    auto obj = make_object(&hull, kPose);
    for (double d : {-1e-7, -1e-9, -1e-13, 0.0, 1e-13, 1e-10, 1e-8, 1e-7, 1e-5}) {
      const ParticleContact c = query(*obj, kPose.to_world(D3(0.5 + m + d, 0.1, 0.05)));
      EXPECT_NEAR(c.distance, d, kGjkTol) << "d = " << d;
      expect_vec(c.normal, kPose.R * D3::UnitX(), kGjkTol, "face normal");
    }
  }
}

TEST(NarrowphaseMesh, NormalIsTheFaceNormalRightAtTheSurface) {
  btTriangleMesh mesh;
  mesh.addTriangle(btVector3(-1, 0, -1), btVector3(-1, 0, 2), btVector3(2, 0, -1));
  btBvhTriangleMeshShape shape(&mesh, true);
  auto obj = make_object(&shape, kPose);
  for (double d : {-1e-9, -1e-13, 0.0, 1e-13, 1e-11, 1e-9}) {
    const ParticleContact c = query(*obj, kPose.to_world(D3(0.25, d, 0.25)), 0.1);
    EXPECT_NEAR(c.distance, d, tol_at(kPose.t)) << "d = " << d;
    expect_vec(c.normal, kPose.R * D3::UnitY(), tol_at(kPose.t), "face normal");
  }
}

// ---------------------------------------------------------------- compound
TEST(NarrowphaseCompound, NearestChildWins) {
  // Children: a sphere (r 0.5) at (-1, 0, 0) and a box (half 0.4) at (1, 0, 0)
  // turned 45 degrees about y; the compound itself is moved by kPose.
  btSphereShape sphere(0.5);
  btBoxShape box(btVector3(0.4, 0.4, 0.4));
  btCompoundShape compound;
  const Pose child_s = make_pose(D3::UnitX(), 0, D3(-1, 0, 0));
  const Pose child_b = make_pose(D3::UnitY(), M_PI / 4, D3(1, 0, 0));
  compound.addChildShape(to_bt(child_s), &sphere);
  compound.addChildShape(to_bt(child_b), &box);
  auto obj = make_object(&compound, kPose);
  auto sdf = [&](const D3& p) {
    return std::min(ref_sphere(0.5, child_s.to_local(p)), ref_box(D3(0.4, 0.4, 0.4), child_b.to_local(p)));
  };
  // Known answers in the compound frame: next to the sphere, next to the box's
  // rotated face, and between them at x = -0.2 (sphere surface at x = -0.5,
  // box edge at x = 1 - 0.4 sqrt(2) = 0.434: the sphere is nearer, 0.3 vs 0.634).
  ParticleContact c = query(*obj, kPose.to_world(D3(-1, 0.8, 0)));
  EXPECT_NEAR(c.distance, 0.3, kT);
  expect_vec(c.normal, kPose.R * D3::UnitY(), kT, "sphere child normal");
  c = query(*obj, kPose.to_world(D3(1, 0.6, 0)));
  EXPECT_NEAR(c.distance, 0.2, kT);
  expect_vec(c.normal, kPose.R * D3::UnitY(), kT, "box child normal");
  c = query(*obj, kPose.to_world(D3(-0.2, 0, 0)));
  EXPECT_NEAR(c.distance, 0.3, kT);
  expect_vec(c.normal, kPose.R * D3::UnitX(), kT, "nearest child normal");
  int failures = 0;
  for (const D3& x : random_points(kPose, 2.0, 2000, 9)) {
    const auto r = matches(*obj, kPose, sdf, x);
    if (!r && ++failures <= 5) ADD_FAILURE() << r.message();
  }
  EXPECT_EQ(failures, 0);
}

// ---------------------------------------------------------------- triangle meshes
namespace {
// A 4 x 4 m ground at y = 0 made of 2 x 2 quads, triangles counter-clockwise
// seen from +y (front = up) unless `flip`.
void add_ground(btTriangleMesh& mesh, bool flip) {
  for (int i = 0; i < 2; ++i)
    for (int k = 0; k < 2; ++k) {
      const btVector3 a(2.0 * i - 2, 0, 2.0 * k - 2), b = a + btVector3(2, 0, 0), c = a + btVector3(2, 0, 2),
                      d = a + btVector3(0, 0, 2);
      // a -> d -> c is counter-clockwise seen from +y: (d - a) x (c - a) = +y.
      if (!flip) {
        mesh.addTriangle(a, d, c);
        mesh.addTriangle(a, c, b);
      } else {
        mesh.addTriangle(a, c, d);
        mesh.addTriangle(a, b, c);
      }
    }
}
}  // namespace

TEST(NarrowphaseMesh, GroundIsOneSided) {
  btTriangleMesh mesh;
  add_ground(mesh, false);
  btBvhTriangleMeshShape shape(&mesh, true);
  const Pose pose = make_pose(D3::UnitX(), 0, D3(0, 1, 0));  // ground at y = 1
  auto obj = make_object(&shape, pose);
  // Above: +0.1, normal up, closest point straight below.
  ParticleContact c = query(*obj, D3(0.3, 1.1, 0.7), 0.2);
  EXPECT_NEAR(c.distance, 0.1, kT);
  expect_vec(c.normal, D3::UnitY(), kT, "above normal");
  expect_vec(c.point, D3(0.3, 1, 0.7), kT, "above point");
  // Below, within the search radius: penetrating by 0.05, normal still up
  // (the particle is pushed back to the front side).
  c = query(*obj, D3(0.3, 0.95, 0.7), 0.2);
  EXPECT_NEAR(c.distance, -0.05, kT);
  expect_vec(c.normal, D3::UnitY(), kT, "below normal");
  expect_vec(c.point, D3(0.3, 1, 0.7), kT, "below point");
  // On a shared edge and at a shared vertex of four triangles: same answer.
  EXPECT_NEAR(query(*obj, D3(0, 1.1, 0.7), 0.2).distance, 0.1, kT);
  EXPECT_NEAR(query(*obj, D3(0, 0.9, 0), 0.2).distance, -0.1, kT);
  // With the winding flipped the front is down: the same point above is behind.
  btTriangleMesh flipped;
  add_ground(flipped, true);
  btBvhTriangleMeshShape flipped_shape(&flipped, true);
  auto flipped_obj = make_object(&flipped_shape, pose);
  c = query(*flipped_obj, D3(0.3, 1.1, 0.7), 0.2);
  EXPECT_NEAR(c.distance, -0.1, kT);
  expect_vec(c.normal, -D3::UnitY(), kT, "flipped normal");
}

TEST(NarrowphaseMesh, SpeculativeMarginIsTheSearchRadiusOnBothSides) {
  btTriangleMesh mesh;
  add_ground(mesh, false);
  btBvhTriangleMeshShape shape(&mesh, true);
  auto obj = make_object(&shape, Pose{});
  ParticleContact c;
  c.distance = 42;
  EXPECT_FALSE(query_point(*obj, Vec3(0.3, 0.11, 0.7), Real(0.1), c));   // 0.11 above
  EXPECT_FALSE(query_point(*obj, Vec3(0.3, -0.11, 0.7), Real(0.1), c));  // 0.11 below (thin shell)
  EXPECT_EQ(c.distance, 42) << "out must be untouched without a contact";
  EXPECT_TRUE(query_point(*obj, Vec3(0.3, 0.09, 0.7), Real(0.1), c));
  EXPECT_NEAR(c.distance, 0.09, kT);
  EXPECT_TRUE(query_point(*obj, Vec3(0.3, -0.09, 0.7), Real(0.1), c));
  EXPECT_NEAR(c.distance, -0.09, kT);
  // Beyond the mesh's border (x > 2): the closest feature is the border edge.
  EXPECT_TRUE(query_point(*obj, Vec3(2.06, 0.08, 0), Real(0.11), c));
  EXPECT_NEAR(c.distance, 0.1, kT);
  expect_vec(c.normal, D3(0.6, 0.8, 0), kT, "border normal");
}

TEST(NarrowphaseMesh, ClosedCubeMeshMatchesTheBoxNearItsSurface) {
  // A closed, outward-wound cube mesh has the box's signed distance within the
  // search radius, also at points whose nearest feature is an edge or a corner
  // shared by several triangles (where the side is chosen by the triangle
  // whose plane faces the point).
  const D3 h(0.5, 0.3, 0.2);
  btTriangleMesh mesh;
  add_box_triangles(mesh, h);
  btBvhTriangleMeshShape shape(&mesh, true);
  auto obj = make_object(&shape, kPose);
  auto sdf = [&](const D3& p) { return ref_box(h, p); };
  const double radius = 0.25;
  int failures = 0, tested = 0;
  for (const D3& x : random_points(kPose, 0.8, 4000, 21)) {
    if (std::abs(sdf(kPose.to_local(x))) > radius * 0.999) continue;
    ++tested;
    ParticleContact c;
    if (!query_point(*obj, vec(x), Real(radius), c)) {
      if (++failures <= 5) ADD_FAILURE() << "no contact at " << x.transpose();
      continue;
    }
    const auto r = matches(*obj, kPose, sdf, x);
    if (!r && ++failures <= 5) ADD_FAILURE() << r.message();
  }
  EXPECT_EQ(failures, 0);
  EXPECT_GT(tested, 1000);
  // Points straight out from an edge and a corner (ties between 2 and 3 triangles).
  EXPECT_TRUE(matches(*obj, kPose, sdf, kPose.to_world(D3(0.6, 0.4, 0))));
  EXPECT_TRUE(matches(*obj, kPose, sdf, kPose.to_world(D3(0.6, 0.4, 0.3))));
  EXPECT_TRUE(matches(*obj, kPose, sdf, kPose.to_world(D3(0.6, 0.3, 0.1))));  // on the +y face's plane
}

TEST(NarrowphaseMesh, ScaledBvhMeshIsScaled) {
  // The unit-cube mesh (half 0.5) scaled by (2, 1, 0.5) is the box of half (1, 0.5, 0.25).
  btTriangleMesh mesh;
  add_box_triangles(mesh, D3(0.5, 0.5, 0.5));
  btBvhTriangleMeshShape base(&mesh, true);
  btScaledBvhTriangleMeshShape shape(&base, btVector3(2, 1, 0.5));
  auto obj = make_object(&shape, kPose);
  auto sdf = [&](const D3& p) { return ref_box(D3(1, 0.5, 0.25), p); };
  int failures = 0;
  for (const D3& x : random_points(kPose, 1.3, 3000, 4)) {
    if (std::abs(sdf(kPose.to_local(x))) > 0.2) continue;
    const auto r = matches(*obj, kPose, sdf, x);
    if (!r && ++failures <= 5) ADD_FAILURE() << r.message();
  }
  EXPECT_EQ(failures, 0);
}

TEST(NarrowphaseHeightfield, SlopedTerrainIsAPlaneWithItsFrontUp) {
  // 5 x 5 samples 1 m apart, height 0.5 * i along x. Bullet centres the
  // terrain on its AABB: local x = i - 2, local y = h - (0 + 2) / 2, so the
  // surface is the plane y = 0.5 x, outward normal (-0.5, 1, 0) / sqrt(1.25).
  static float heights[25];
  for (int k = 0; k < 5; ++k)
    for (int i = 0; i < 5; ++i) heights[k * 5 + i] = 0.5f * float(i);
  const D3 n = D3(-0.5, 1, 0) / std::sqrt(1.25);
  for (bool flip_winding : {false, true}) {
    SCOPED_TRACE(flip_winding ? "flipped winding" : "default winding");
    btHeightfieldTerrainShape shape(5, 5, heights, btScalar(0), btScalar(2), 1, false);
    shape.setFlipTriangleWinding(flip_winding);
    auto obj = make_object(&shape, kPose);
    for (const D3& p : {D3(0.3, 0.15 + 0.2, -0.4), D3(-1.1, -0.55 - 0.1, 0.9), D3(1.2, 0.6 + 0.05, 1.3)}) {
      const double d_ref = (p - D3(p.x(), 0.5 * p.x(), p.z())).dot(n);
      const ParticleContact c = query(*obj, kPose.to_world(p), 0.3);
      EXPECT_NEAR(c.distance, d_ref, kT) << "local p " << p.transpose();
      expect_vec(c.normal, kPose.R * n, kT, "terrain normal");
    }
  }
}

// ---------------------------------------------------------------- cutoff and input
TEST(NarrowphaseMargin, SpeculativeCutoffForEveryShapeKind) {
  // Each shape has a face whose outward normal is +x with the surface at x = 0.5.
  btSphereShape sphere(0.5);
  btBoxShape box(btVector3(0.5, 0.5, 0.5));
  btConvexHullShape hull;
  for (int i = 0; i < 8; ++i) hull.addPoint(btVector3(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5));
  hull.setMargin(0);
  btCompoundShape compound;
  compound.addChildShape(btTransform::getIdentity(), &box);
  btTriangleMesh mesh;
  add_box_triangles(mesh, D3(0.5, 0.5, 0.5));
  btBvhTriangleMeshShape bvh(&mesh, true);
  btCollisionShape* shapes[] = {&sphere, &box, &hull, &compound, &bvh};
  for (btCollisionShape* s : shapes) {
    SCOPED_TRACE(s->getName());
    auto obj = make_object(s, kPose);
    ParticleContact c;
    EXPECT_FALSE(query_point(*obj, vec(kPose.to_world(D3(0.61, 0, 0))), Real(0.1), c));
    ASSERT_TRUE(query_point(*obj, vec(kPose.to_world(D3(0.59, 0, 0))), Real(0.1), c));
    EXPECT_NEAR(c.distance, 0.09, kGjkTol);
    // On the surface (up to the round-off of the pose) with a zero-width margin.
    ASSERT_TRUE(query_point(*obj, vec(kPose.to_world(D3(0.5, 0, 0))), Real(kGjkTol), c));
    EXPECT_NEAR(c.distance, 0, kGjkTol);
  }
}

TEST(NarrowphaseInput, BadArgumentsAreNamed) {
  btSphereShape sphere(0.5);
  auto obj = make_object(&sphere, Pose{});
  ParticleContact c;
  auto message = [](auto&& f) {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  std::string m = message([&] { query_point(*obj, Vec3(0, nan, 0), Real(0.1), c); });
  EXPECT_NE(m.find("x = (0, nan, 0)"), std::string::npos) << m;
  m = message([&] { query_point(*obj, Vec3(0, 0, 0), Real(-0.5), c); });
  EXPECT_NE(m.find("max_distance = -0.5"), std::string::npos) << m;
  m = message([&] { query_point(*obj, Vec3(0, 0, 0), std::numeric_limits<Real>::infinity(), c); });
  EXPECT_NE(m.find("max_distance = inf"), std::string::npos) << m;
  Real f;
  m = message([&] { xpbd_bullet::sweep_point(*obj, Vec3(0, 0, 0), Vec3(nan, 0, 0), c, f); });
  EXPECT_NE(m.find("b = (nan, 0, 0)"), std::string::npos) << m;
}

TEST(NarrowphaseInput, UnsupportedShapesGiveNoContact) {
  btEmptyShape empty;
  auto obj = make_object(&empty, Pose{});
  ParticleContact c;
  EXPECT_FALSE(xpbd_bullet::is_supported(empty));
  EXPECT_FALSE(query_point(*obj, Vec3(0, 0, 0), Real(1), c));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
