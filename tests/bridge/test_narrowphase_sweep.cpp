// Known-answer tests of sweep_point (tunnelling prevention) and candidates()
// (broadphase), docs/design.md section 4.
//
// Sweep fractions from closed forms are exact up to round-off; the root finder
// used for capsules, cylinders and hulls stops at ~64 eps * |x| m, so fractions
// of segments of length L >= 0.8 m agree to 1e-12 with the closed forms (the
// hull's GJK distance is good to ~1e-12 m, hence 1e-9 there).
#include <gtest/gtest.h>

#include <BulletCollision/CollisionDispatch/btGhostObject.h>
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <btBulletCollisionCommon.h>

#include <algorithm>
#include <functional>
#include <set>

#include "test_narrowphase_util.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace np_test;
using xpbd_bullet::ParticleContact;
using xpbd_bullet::query_point;
using xpbd_bullet::sweep_point;

namespace {

constexpr double kFracTol = std::is_same_v<Real, double> ? 1e-12 : 1e-4;
constexpr double kGjkFracTol = std::is_same_v<Real, double> ? 1e-9 : 2e-3;

const Pose kPose = make_pose(D3(-0.3, 1, 0.4), 0.9, D3(-2, 0.5, 1));  // an arbitrary rigid motion

struct Hit {
  bool hit = false;
  ParticleContact c;
  Real t = -1;
};

// Sweep of the local segment a -> b (local frame of pose) against obj.
Hit sweep_local(const btCollisionObject& obj, const Pose& pose, const D3& a, const D3& b) {
  Hit h;
  h.hit = sweep_point(obj, vec(pose.to_world(a)), vec(pose.to_world(b)), h.c, h.t);
  return h;
}

// Checks a hit against the expected local fraction, normal and hit point, and
// that out.distance is the end point's distance from the tangent plane.
void expect_hit(const Hit& h, const Pose& pose, const D3& a, const D3& b, double t, const D3& n_local,
                double tol) {
  ASSERT_TRUE(h.hit) << "expected a hit at t = " << t;
  EXPECT_NEAR(h.t, t, tol);
  const D3 n = pose.R * n_local, p = pose.to_world(a + t * (b - a));
  EXPECT_LE((d3(h.c.normal) - n).norm(), tol) << h.c.normal.transpose() << " vs " << n.transpose();
  EXPECT_LE((d3(h.c.point) - p).norm(), tol * (b - a).norm() + tol) << h.c.point.transpose() << " vs " << p.transpose();
  EXPECT_NEAR(h.c.distance, (pose.to_world(b) - p).dot(n), tol * (b - a).norm() + tol);
}

}  // namespace

// ------------------------------------------------------------------ thin plate
TEST(NarrowphaseSweep, FastParticleHitsTheNearFaceOfAThinPlate) {
  // A particle at 50 m/s for one 1/60 s step crosses a 1 cm plate (half
  // thickness 0.005 m): it starts 0.4 m above the plate's centre plane and
  // ends 0.433 m below it, so a discrete query at either end finds nothing.
  // The near face (y = +0.005) is reached at t = (0.4 - 0.005) / (50 / 60) = 0.474.
  const double dt = 1.0 / 60, speed = 50;
  const D3 a(0.1, 0.4, 0.2), b = a + dt * D3(0, -speed, 0);
  const double t_exact = (0.4 - 0.005) / (speed * dt);
  ASSERT_NEAR(t_exact, 0.474, 1e-15);

  btBoxShape box(btVector3(1, 0.005, 1));
  btConvexHullShape hull;
  for (int i = 0; i < 8; ++i) hull.addPoint(btVector3(i & 1 ? 1 : -1, i & 2 ? 0.005 : -0.005, i & 4 ? 1 : -1));
  hull.setMargin(0);
  btCompoundShape compound;
  compound.addChildShape(btTransform::getIdentity(), &box);
  btTriangleMesh mesh;
  add_box_triangles(mesh, D3(1, 0.005, 1));
  btBvhTriangleMeshShape bvh(&mesh, true);
  struct Case {
    btCollisionShape* shape;
    double tol;
  } cases[] = {{&box, kFracTol}, {&hull, kGjkFracTol}, {&compound, kFracTol}, {&bvh, kFracTol}};
  for (const Case& k : cases) {
    SCOPED_TRACE(k.shape->getName());
    auto obj = make_object(k.shape, kPose);
    ParticleContact c;
    EXPECT_FALSE(query_point(*obj, vec(kPose.to_world(a)), Real(0.05), c));
    EXPECT_FALSE(query_point(*obj, vec(kPose.to_world(b)), Real(0.05), c)) << "the step tunnels";
    expect_hit(sweep_local(*obj, kPose, a, b), kPose, a, b, t_exact, D3::UnitY(), k.tol);
    // Obliquely at 50 m/s, direction (0.6, -0.8, 0): the y speed is 40 m/s.
    const D3 b2 = a + dt * speed * D3(0.6, -0.8, 0);
    expect_hit(sweep_local(*obj, kPose, a, b2), kPose, a, b2, (0.4 - 0.005) / (40 * dt), D3::UnitY(), k.tol);
    // From below it hits the lower face.
    const D3 a3(0.1, -0.4, 0.2), b3(0.1, 0.4, 0.2);
    expect_hit(sweep_local(*obj, kPose, a3, b3), kPose, a3, b3, 0.395 / 0.8, -D3::UnitY(), k.tol);
    // Misses: beside the plate, and stopping short of it.
    EXPECT_FALSE(sweep_local(*obj, kPose, D3(1.2, 0.4, 0), D3(1.2, -0.4, 0)).hit);
    EXPECT_FALSE(sweep_local(*obj, kPose, a, D3(0.1, 0.006, 0.2)).hit);
  }
}

// ------------------------------------------------------------------ primitives
TEST(NarrowphaseSweep, SphereCapsuleCylinderPlaneClosedForms) {
  btSphereShape sphere(0.5);
  auto so = make_object(&sphere, kPose);
  // Line y = 0.3 crosses x^2 + 0.09 = 0.25 at x = -0.4: t = (2 - 0.4) / 4.
  expect_hit(sweep_local(*so, kPose, D3(-2, 0.3, 0), D3(2, 0.3, 0)), kPose, D3(-2, 0.3, 0), D3(2, 0.3, 0), 0.4,
             D3(-0.4, 0.3, 0) / 0.5, kFracTol);
  EXPECT_FALSE(sweep_local(*so, kPose, D3(-2, 0.6, 0), D3(2, 0.6, 0)).hit);     // passes beside
  EXPECT_FALSE(sweep_local(*so, kPose, D3(-2, 0.3, 0), D3(-0.41, 0.3, 0)).hit);  // stops short

  btCapsuleShape capsule(0.3, 1.0);  // Y axis, half height 0.5
  auto co = make_object(&capsule, kPose);
  {  // Barrel at z = 0.1: x^2 + 0.01 = 0.09, x = -sqrt(0.08).
    const D3 a(-2, 0.2, 0.1), b(2, 0.2, 0.1);
    const double x = -std::sqrt(0.08);
    expect_hit(sweep_local(*co, kPose, a, b), kPose, a, b, (x + 2) / 4, D3(x, 0, 0.1) / 0.3, kFracTol);
  }
  {  // Down onto the top hemisphere (centre y = 0.5) at x = 0.1: y = 0.5 + sqrt(0.08).
    const D3 a(0.1, 2, 0), b(0.1, -2, 0);
    const double y = 0.5 + std::sqrt(0.08);
    expect_hit(sweep_local(*co, kPose, a, b), kPose, a, b, (2 - y) / 4, D3(0.1, y - 0.5, 0) / 0.3, kFracTol);
  }
  EXPECT_FALSE(sweep_local(*co, kPose, D3(0.31, 2, 0), D3(0.31, -2, 0)).hit);  // beside the barrel

  btCylinderShapeZ cylinder(btVector3(0.4, 0.4, 0.6));  // radius 0.4, half height 0.6
  auto yo = make_object(&cylinder, kPose);
  {  // Down the z axis at radial 0.2 onto the cap z = 0.6.
    const D3 a(0.2, 0, 2), b(0.2, 0, -2);
    expect_hit(sweep_local(*yo, kPose, a, b), kPose, a, b, 1.4 / 4, D3::UnitZ(), kFracTol);
  }
  {  // Across the barrel at y = 0.1: x = -sqrt(0.15).
    const D3 a(-2, 0.1, 0.1), b(2, 0.1, 0.1);
    const double x = -std::sqrt(0.15);
    expect_hit(sweep_local(*yo, kPose, a, b), kPose, a, b, (x + 2) / 4, D3(x, 0.1, 0) / 0.4, kFracTol);
  }
  // Parallel to the barrel at radial 0.4 + 1e-6: grazes without touching.
  EXPECT_FALSE(sweep_local(*yo, kPose, D3(0.400001, 0, 2), D3(0.400001, 0, -2)).hit);

  btStaticPlaneShape plane(btVector3(0, 1, 0), 0.5);
  auto po = make_object(&plane, kPose);
  {  // From 0.3 above to 0.1 below: t = 0.3 / 0.4.
    const D3 a(5, 0.8, -3), b(6, 0.4, -3);
    expect_hit(sweep_local(*po, kPose, a, b), kPose, a, b, 0.75, D3::UnitY(), kFracTol);
  }
  EXPECT_FALSE(sweep_local(*po, kPose, D3(0, 0.8, 0), D3(0, 0.51, 0)).hit);
}

TEST(NarrowphaseSweep, StartingInsideHitsAtZero) {
  btBoxShape box(btVector3(1, 0.5, 0.25));
  auto obj = make_object(&box, kPose);
  // Inside, nearest the +z face (0.2 away); moving along +x.
  const D3 a(0.3, 0.1, 0.05), b(0.8, 0.1, 0.05);
  const Hit h = sweep_local(*obj, kPose, a, b);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 0);
  EXPECT_LE((d3(h.c.normal) - kPose.R * D3::UnitZ()).norm(), kT);
  EXPECT_LE((d3(h.c.point) - kPose.to_world(D3(0.3, 0.1, 0.25))).norm(), kT);
  EXPECT_NEAR(h.c.distance, -0.2, kT);  // b is 0.2 below the +z face's plane
}

// Random segments against capsule, cylinder and cube hull, compared with the
// first entry found on the test's own reference SDF: 4000 samples along the
// segment (at most 1.3 mm apart), then bisection of the reference between the
// last outside and the first inside sample. Segments whose sampled minimum is
// within 1e-2 m of 0 are skipped: a chord that dips less than 1 cm into a
// box corner or a 0.3 m radius can be shorter than the sample spacing.
TEST(NarrowphaseSweep, RandomSegmentsMatchSampledReference) {
  btCapsuleShapeX capsule(0.3, 1.2);
  btCylinderShape cylinder(btVector3(0.4, 0.6, 0.4));
  btConvexHullShape hull;
  const D3 h(0.5, 0.3, 0.2);
  for (int i = 0; i < 8; ++i) hull.addPoint(btVector3(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z()));
  hull.setMargin(0);
  struct Case {
    const char* name;
    btCollisionShape* shape;
    std::function<double(const D3&)> sdf;
    double tol;
  } cases[] = {
      {"capsule X", &capsule, [](const D3& p) { return ref_capsule(0, 0.3, 0.6, p); }, kGjkFracTol},
      {"cylinder Y", &cylinder, [](const D3& p) { return ref_cylinder(1, 0.4, 0.6, p); }, kGjkFracTol},
      {"cube hull", &hull, [&](const D3& p) { return ref_box(h, p); }, kGjkFracTol},
  };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.5, 1.5), v(-0.8, 0.8);  // ends b nearer the shape
  for (const Case& k : cases) {
    SCOPED_TRACE(k.name);
    auto obj = make_object(k.shape, kPose);
    int hits = 0, misses = 0, failures = 0;
    for (int s = 0; s < 200; ++s) {
      const D3 a(u(rng), u(rng), u(rng)), b(v(rng), v(rng), v(rng));
      if (k.sdf(a) <= 1e-2) continue;  // start outside
      const int n = 4000;
      int first = -1;
      double min_f = 1e9;
      for (int i = 0; i <= n; ++i) {
        const double f = k.sdf(a + (double(i) / n) * (b - a));
        min_f = std::min(min_f, f);
        if (f <= 0 && first < 0) first = i;
      }
      if (std::abs(min_f) < 1e-2) continue;
      const Hit got = sweep_local(*obj, kPose, a, b);
      if (first < 0) {
        ++misses;
        if (got.hit && ++failures <= 5) ADD_FAILURE() << "false hit at t=" << got.t;
        continue;
      }
      ++hits;
      double lo = double(first - 1) / n, hi = double(first) / n;
      for (int i = 0; i < 100; ++i) {
        const double mid = 0.5 * (lo + hi);
        (k.sdf(a + mid * (b - a)) > 0 ? lo : hi) = mid;
      }
      if (!got.hit || std::abs(got.t - hi) > k.tol) {
        if (++failures <= 5) ADD_FAILURE() << "t=" << got.t << " (hit " << got.hit << "), reference " << hi;
        continue;
      }
      // The hit point is on the surface.
      const double on = k.sdf(kPose.to_local(d3(got.c.point)));
      if (std::abs(on) > k.tol && ++failures <= 5) ADD_FAILURE() << "hit point off the surface by " << on;
    }
    EXPECT_EQ(failures, 0);
    EXPECT_GT(hits, 30);  // both outcomes are exercised
    EXPECT_GT(misses, 10);
  }
}

// ------------------------------------------------------------------ meshes
TEST(NarrowphaseSweep, MeshesAreHitOnTheirFrontOnly) {
  // Ground quad 4 x 4 m at y = 0 split along its diagonal, front up.
  btTriangleMesh mesh;
  const btVector3 p00(-2, 0, -2), p10(2, 0, -2), p11(2, 0, 2), p01(-2, 0, 2);
  mesh.addTriangle(p00, p01, p11);  // (p01 - p00) x (p11 - p00) = +y
  mesh.addTriangle(p00, p11, p10);
  btBvhTriangleMeshShape shape(&mesh, true);
  auto obj = make_object(&shape, kPose);
  const D3 a(0.3, 0.5, 0.2), b(0.3, -0.5, 0.2);
  expect_hit(sweep_local(*obj, kPose, a, b), kPose, a, b, 0.5, D3::UnitY(), kFracTol);
  EXPECT_FALSE(sweep_local(*obj, kPose, b, a).hit) << "leaving through the back is no hit";
  // Exactly through the shared diagonal edge (x = z) and a shared vertex: no leak.
  expect_hit(sweep_local(*obj, kPose, D3(0.7, 0.5, 0.7), D3(0.7, -0.5, 0.7)), kPose, D3(0.7, 0.5, 0.7),
             D3(0.7, -0.5, 0.7), 0.5, D3::UnitY(), kFracTol);
  expect_hit(sweep_local(*obj, kPose, D3(-2, 0.5, -2), D3(-2, -0.5, -2)), kPose, D3(-2, 0.5, -2),
             D3(-2, -0.5, -2), 0.5, D3::UnitY(), kFracTol);
}

TEST(NarrowphaseSweep, HeightfieldIsHitFromItsUpSide) {
  // The sloped terrain of the query test: the plane y = 0.5 x, normal (-0.5, 1, 0) / sqrt(1.25).
  static float heights[25];
  for (int k = 0; k < 5; ++k)
    for (int i = 0; i < 5; ++i) heights[k * 5 + i] = 0.5f * float(i);
  btHeightfieldTerrainShape shape(5, 5, heights, btScalar(0), btScalar(2), 1, false);
  shape.setFlipTriangleWinding(true);  // the front is the up side whatever the winding
  auto obj = make_object(&shape, kPose);
  // Straight down at x = 0.6 from y = 1 to y = -1: the surface is at y = 0.3.
  const D3 a(0.6, 1, 0.3), b(0.6, -1, 0.3);
  expect_hit(sweep_local(*obj, kPose, a, b), kPose, a, b, 0.7 / 2, D3(-0.5, 1, 0) / std::sqrt(1.25), kFracTol);
  EXPECT_FALSE(sweep_local(*obj, kPose, b, a).hit);
}

// ------------------------------------------------------------------ broadphase
namespace {
struct World {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btCollisionWorld world{&dispatcher, &broadphase, &config};
};

bool overlaps(const D3& lo1, const D3& hi1, const D3& lo2, const D3& hi2) {
  return (lo1.array() <= hi2.array()).all() && (lo2.array() <= hi1.array()).all();
}
}  // namespace

TEST(NarrowphaseBroadphase, CandidatesAreExactlyTheOverlappingAabbs) {
  // 100 spheres (radius 0.3) on a 10 x 10 grid 1 m apart in the y = 0 plane;
  // a sphere's AABB is its centre +- 0.3. Every 7th sphere is in filter
  // group 2, which the query's mask excludes.
  World w;
  btSphereShape shape(0.3);
  std::vector<std::unique_ptr<btCollisionObject>> spheres;
  std::vector<D3> centres;
  for (int i = 0; i < 10; ++i)
    for (int k = 0; k < 10; ++k) {
      centres.emplace_back(i, 0, k);
      spheres.push_back(make_object(&shape, make_pose(D3::UnitX(), 0, centres.back())));
      const int group = spheres.size() % 7 == 0 ? 2 : 1;
      w.world.addCollisionObject(spheres.back().get(), group, -1);
    }
  // Never candidates: a trigger without contact response, and a ghost object.
  btBoxShape big(btVector3(20, 20, 20));
  auto trigger = make_object(&big, Pose{});
  trigger->setCollisionFlags(btCollisionObject::CF_NO_CONTACT_RESPONSE);
  w.world.addCollisionObject(trigger.get());
  btGhostObject ghost;
  ghost.setCollisionShape(&big);
  w.world.addCollisionObject(&ghost);

  auto check = [&](double inflate) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1, 10), size(0, 3);
    std::vector<const btCollisionObject*> got;
    int nonempty = 0, empty = 0;
    for (int q = 0; q < 300; ++q) {
      const D3 lo(u(rng), u(rng) * 0.1, u(rng)), hi = lo + D3(size(rng), size(rng), size(rng));
      xpbd_bullet::candidates(w.world, vec(lo), vec(hi), got, 1, 1);
      std::set<const btCollisionObject*> want, have(got.begin(), got.end());
      for (size_t i = 0; i < centres.size(); ++i) {
        const D3 r = D3::Constant(0.3 + inflate);
        if ((i + 1) % 7 != 0 && overlaps(centres[i] - r, centres[i] + r, lo, hi)) want.insert(spheres[i].get());
      }
      EXPECT_EQ(have.size(), got.size()) << "duplicates";
      EXPECT_EQ(have, want) << "query " << lo.transpose() << " .. " << hi.transpose();
      nonempty += !want.empty();
      empty += want.empty();
    }
    EXPECT_GT(nonempty, 50);  // both outcomes are exercised
    EXPECT_GT(empty, 50);
  };
  // Right after addCollisionObject the proxy AABB is the shape's AABB.
  check(0);
  // updateAabbs (run by every stepSimulation) grows each AABB by
  // gContactBreakingThreshold (Bullet's btCollisionWorld::updateSingleAabb).
  w.world.updateAabbs();
  check(gContactBreakingThreshold);

  for (auto& s : spheres) w.world.removeCollisionObject(s.get());
  w.world.removeCollisionObject(trigger.get());
  w.world.removeCollisionObject(&ghost);
}

TEST(NarrowphaseBroadphase, RejectsAnInvertedBox) {
  World w;
  std::vector<const btCollisionObject*> out;
  try {
    xpbd_bullet::candidates(w.world, Vec3(0, 1, 0), Vec3(1, 0, 1), out);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("axis 1"), std::string::npos) << e.what();
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
