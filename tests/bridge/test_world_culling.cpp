// Culling of (particle, body) pairs in XpbdWorld's contact generation
// (ContactSettings::cull, bullet_bridge/src/world.cpp).
//
// The culling skips the narrowphase for pairs whose boxes are apart and must
// never drop a contact. The reference is the brute-force path (cull = false),
// which queries every (movable particle, broadphase candidate) pair. Both
// paths run the same narrowphase on the same inputs, so the contacts must be
// identical field by field, in the same order, and the simulations that use
// them bitwise identical. That is checked here on a scene with every shape
// kind the narrowphase supports, static, spinning and moving bodies, pinned
// particles and particles fast enough to take the sweep path; and at the
// culling boundary itself against closed-form distances. The same holds for
// the rigid features against the cloth's collision triangles, found through
// FCL's hierarchy of the triangles (ContactSettings::triangle_bvh_from = 0)
// or by the loop over every triangle, and for the search on 1, 2 or 4
// threads (SystemSettings::workers).
#include <gtest/gtest.h>

#include <array>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "../integration/support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

btTransform pose(const Vec3& x, const btQuaternion& q = btQuaternion::getIdentity()) {
  return btTransform(q, bt(x));
}

// An n x n cloth (16 by default), 1.4 m, 0.45 m up, two corners pinned
// (inverse mass 0: never in a contact); triangles: with collision triangles.
xpbd::ClothGridDesc test_cloth(bool triangles, int n = 16) {
  xpbd::ClothGridDesc d;
  d.nx = d.ny = n;
  d.size_u = d.size_v = Real(1.4);
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  d.origin = Vec3(Real(-0.7), Real(0.45), Real(-0.7));
  d.mass = Real(0.3);
  d.radius = Real(0.004);
  d.bend_mat.compliance = Real(1e-2);
  d.pinned = {{0, 0}, {n - 1, 0}};
  d.collision_triangles = triangles;
  return d;
}

// One Bullet world with the test scene and an XpbdWorld holding a cloth and
// a handful of fast particles. Built identically for both culling modes.
struct Scene {
  // Declared before the world, so that they outlive it: the mesh's triangles
  // and the compound's children (neither shape owns them).
  std::unique_ptr<btTriangleMesh> mesh = std::make_unique<btTriangleMesh>();
  std::vector<std::unique_ptr<btCollisionShape>> children;
  BulletWorld bw;
  std::unique_ptr<XpbdWorld> xw;
  std::vector<std::pair<std::string, btRigidBody*>> bodies;
  xpbd_bullet::SystemId cloth, shots;

  // triangles: the cloth has collision triangles, and bvh_from is its
  // ContactSettings::triangle_bvh_from.
  // pool: a thread pool for the systems (SystemSettings::workers, with the
  // coloured sweep it needs), or null; cloth_n: the cloth's size;
  // edge_contacts: ContactSettings::edge_contacts (off, a box's features are
  // also the points along its edges).
  explicit Scene(bool cull, bool triangles = false, int bvh_from = 0, xpbd::Workers* pool = nullptr,
                 int cloth_n = 16, bool edge_contacts = true) {
    auto add = [&](const std::string& name, btRigidBody* b) { bodies.emplace_back(name, b); };
    add("plane", bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, pose(Vec3::Zero())));
    add("sphere", bw.add_static_sphere(Real(0.15), Vec3(Real(-0.3), Real(0.15), Real(-0.3))));
    add("box", bw.add_static_box(Vec3(Real(0.12), Real(0.1), Real(0.12)),
                                 pose(Vec3(Real(0.3), Real(0.12), Real(-0.3)),
                                      btQuaternion(btVector3(1, 1, 0).normalized(), Real(0.5)))));
    add("capsule", bw.add_body(new btCapsuleShapeX(Real(0.06), Real(0.3)), 0,
                               pose(Vec3(Real(-0.3), Real(0.08), Real(0.3)))));
    add("cylinder", bw.add_body(new btCylinderShape(btVector3(Real(0.1), Real(0.12), Real(0.1))), 0,
                                pose(Vec3(Real(0.3), Real(0.12), Real(0.3)))));
    add("cone", bw.add_body(new btConeShape(Real(0.1), Real(0.25)), 0, pose(Vec3(0, Real(0.12), 0))));
    {
      auto* hull = new btConvexHullShape();
      for (int a = 0; a < 3; ++a)
        for (Real s : {Real(-0.1), Real(0.1)}) {
          Vec3 p = Vec3::Zero();
          p[a] = s;
          hull->addPoint(bt(p));
        }
      add("hull", bw.add_body(hull, 0, pose(Vec3(0, Real(0.1), Real(-0.45)))));
    }
    {
      auto* compound = new btCompoundShape();
      children.emplace_back(new btBoxShape(btVector3(Real(0.05), Real(0.1), Real(0.05))));
      compound->addChildShape(pose(Vec3(Real(-0.08), 0, 0)), children.back().get());
      children.emplace_back(new btSphereShape(Real(0.06)));
      compound->addChildShape(pose(Vec3(Real(0.08), 0, 0)), children.back().get());
      add("compound", bw.add_body(compound, 0, pose(Vec3(0, Real(0.1), Real(0.45)))));
    }
    {
      // Two triangles of a flat square, wound counter-clockwise seen from +y
      // (their front side is up), around x = -0.6 m (a pose of its own, not
      // the plane's: bodies are told apart by their poses below).
      const Real y = Real(0.05), x0 = Real(-0.15), x1 = Real(0.15), z0 = Real(-0.2), z1 = Real(0.2);
      mesh->addTriangle(btVector3(x0, y, z0), btVector3(x0, y, z1), btVector3(x1, y, z0));
      mesh->addTriangle(btVector3(x1, y, z1), btVector3(x1, y, z0), btVector3(x0, y, z1));
      add("mesh", bw.add_body(new btBvhTriangleMeshShape(mesh.get(), true), 0, pose(Vec3(Real(-0.6), 0, 0))));
    }
    // Dynamic bodies: a small box spinning fast (its angular travel w extent dt
    // enters the culling box) falling onto the cloth, and a sphere rolling in
    // under it. Their masses differ, so that shadows can be told apart.
    btRigidBody* spinner = bw.add_body(new btBoxShape(btVector3(Real(0.05), Real(0.05), Real(0.05))),
                                       Real(0.5), pose(Vec3(Real(0.1), Real(0.9), 0)));
    spinner->setAngularVelocity(btVector3(0, 20, 8));  // rad/s
    add("spinner", spinner);
    add("roller", bw.add_body(new btSphereShape(Real(0.08)), Real(2), pose(Vec3(-1, Real(0.08), 0)),
                              Vec3(3, 0, 0)));

    xw = std::make_unique<XpbdWorld>(bw.world());
    SystemSettings set;
    set.iterations = 2;
    set.contacts.cull = cull;
    set.contacts.surface_edge_contacts = true;  // the cloth's edges against the box edges too
    set.contacts.triangle_bvh_from = bvh_from;
    set.contacts.edge_contacts = edge_contacts;
    set.workers = pool;
    set.coloured = pool != nullptr;
    {
      xpbd::SceneDesc scene;
      xpbd::add_cloth_grid(scene, test_cloth(triangles, cloth_n));
      System s = make_system(scene);
      cloth = xw->add_system(s.model, s.state, set);
    }
    {
      // Free particles shot straight down at 30 m/s from 1 m above the bodies:
      // 0.5 m per step, far beyond the margin, so they take the sweep path.
      xpbd::SceneDesc scene;
      for (const auto& [name, b] : bodies) {
        if (b->getInvMass() != Real(0) || name == "plane") continue;
        btVector3 lo, hi;
        b->getCollisionShape()->getAabb(b->getWorldTransform(), lo, hi);
        const Vec3 c = Real(0.5) * vec(lo + hi);
        scene.positions.push_back(Vec3(c.x(), 1, c.z()));
        scene.masses.push_back(Real(0.01));
        scene.velocities.push_back(Vec3(0, -30, 0));
        scene.radii.push_back(Real(0.01));
      }
      System s = make_system(scene);
      shots = xw->add_system(s.model, s.state, set);
    }
  }

  // Name of the body behind shadow `k` of system `id`: static bodies by their
  // start pose (equal to their pose, exactly), dynamic ones by inverse mass.
  std::string body_name(xpbd_bullet::SystemId id, Index k) const {
    const xpbd::RigidBody& r = xw->state(id).bodies[std::size_t(k)];
    for (const auto& [name, b] : bodies) {
      if (b->getInvMass() != r.inv_mass) continue;
      if (r.inv_mass != Real(0) || vec(b->getWorldTransform().getOrigin()) == r.x) return name;
    }
    return "?";
  }
};

// Exact comparison of two contact lists (same narrowphase, same inputs).
void expect_same_contacts(const std::vector<xpbd::BodyContact>& a, const std::vector<xpbd::BodyContact>& b,
                          const std::string& where) {
  ASSERT_EQ(a.size(), b.size()) << where;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const xpbd::BodyContact &p = a[k], &q = b[k];
    ASSERT_TRUE(p.particle == q.particle && p.body == q.body && p.r == q.r && p.n == q.n &&
                p.thickness == q.thickness && p.static_friction == q.static_friction &&
                p.dynamic_friction == q.dynamic_friction && p.restitution == q.restitution &&
                p.compliance == q.compliance)
        << where << ", contact " << k << ": particle " << p.particle << " vs " << q.particle << ", body "
        << p.body << " vs " << q.body;
  }
}

// The same for edge contacts (a box's edges against the soft edges).
void expect_same_edge_contacts(const std::vector<xpbd::BodyEdgeContact>& a,
                               const std::vector<xpbd::BodyEdgeContact>& b, const std::string& where) {
  ASSERT_EQ(a.size(), b.size()) << where;
  for (std::size_t c = 0; c < a.size(); ++c) {
    const xpbd::BodyEdgeContact &p = a[c], &q = b[c];
    ASSERT_TRUE(p.body == q.body && p.a == q.a && p.b == q.b && p.p == q.p && p.out == q.out &&
                p.thickness == q.thickness && p.reach == q.reach && p.closing_speed == q.closing_speed)
        << where << ", edge contact " << c;
  }
}

TEST(WorldCulling, SameContactsAndTrajectoriesAsBruteForceOnEveryShapeKind) {
  Scene culled(true), brute(false);
  std::map<std::string, int> contacts_per_body;  // culled run, over all steps
  long queries_culled = 0, queries_brute = 0;
  int shot_contacts = 0, edge_contacts = 0;
  const int steps = 60;  // 1 s
  for (int k = 0; k < steps; ++k) {
    culled.bw.step();
    brute.bw.step();
    const auto& sc = culled.xw->last_stats();
    const auto& sb = brute.xw->last_stats();
    const std::string where = "step " + std::to_string(k);
    ASSERT_EQ(sc.candidates, sb.candidates) << where;
    ASSERT_EQ(sc.contacts, sb.contacts) << where;
    ASSERT_EQ(sc.shadows, sb.shadows) << where;
    queries_culled += sc.queries;
    queries_brute += sb.queries;
    for (xpbd_bullet::SystemId id : {culled.cloth, culled.shots}) {
      const xpbd::State& a = culled.xw->state(id);
      const xpbd::State& b = brute.xw->state(id);
      expect_same_contacts(a.contacts, b.contacts, where + ", system " + std::to_string(id.value));
      // The cloth's surface edges against the box edges
      // (ContactSettings::surface_edge_contacts): the culled particles'
      // edges are those of every particle.
      expect_same_edge_contacts(a.edge_contacts, b.edge_contacts, where + ", system " + std::to_string(id.value));
      edge_contacts += static_cast<int>(a.edge_contacts.size());
      // The same contacts give bitwise the same step.
      ASSERT_EQ(a.x, b.x) << where;
      ASSERT_EQ(a.v, b.v) << where;
      const xpbd::Model& m = culled.xw->model(id);
      for (const auto& c : a.contacts) {
        ASSERT_NE(m.inv_mass[c.particle], Real(0)) << where << ": contact on a pinned particle";
        ++contacts_per_body[culled.body_name(id, c.body)];
      }
      if (id == culled.shots) shot_contacts += static_cast<int>(a.contacts.size());
    }
  }
  // The comparison means something only if every shape kind took part and
  // the culling actually skipped pairs.
  for (const auto& [name, b] : culled.bodies) EXPECT_GT(contacts_per_body[name], 0) << name;
  EXPECT_EQ(contacts_per_body["?"], 0);
  EXPECT_GT(shot_contacts, 0);
  EXPECT_GT(edge_contacts, 0);
  EXPECT_LT(queries_culled, queries_brute / 2);
  std::printf("queries over %d steps: %ld culled, %ld brute force\n", steps, queries_culled, queries_brute);
}

// Exact comparison of two triangle contact lists (the hierarchy's and the
// loop's), and of the steps they gave.
void expect_same_triangle_step(const xpbd::State& a, const xpbd::State& b, const std::string& where) {
  ASSERT_EQ(a.triangle_contacts.size(), b.triangle_contacts.size()) << where;
  for (std::size_t c = 0; c < a.triangle_contacts.size(); ++c) {
    const xpbd::BodyTriangleContact &p = a.triangle_contacts[c], &q = b.triangle_contacts[c];
    ASSERT_TRUE(p.body == q.body && p.r == q.r && p.tri == q.tri && p.side == q.side && p.thickness == q.thickness)
        << where << ", triangle contact " << c;
  }
  ASSERT_EQ(a.edge_contacts.size(), b.edge_contacts.size()) << where;
  for (std::size_t c = 0; c < a.edge_contacts.size(); ++c) {
    const xpbd::BodyEdgeContact &p = a.edge_contacts[c], &q = b.edge_contacts[c];
    ASSERT_TRUE(p.body == q.body && p.a == q.a && p.b == q.b && p.p == q.p && p.out == q.out)
        << where << ", edge contact " << c;
  }
  ASSERT_EQ(a.x, b.x) << where;
  ASSERT_EQ(a.v, b.v) << where;
}

// The hierarchy of the collision triangles only filters: every triangle it
// drops fails the loop's own box test, so the triangle contacts (and the
// step) are the loop's, bit for bit, over 1 s of a cloth falling onto
// boxes, a hull, a compound and a fast-spinning box. With the edge
// contacts (the default), a box's features are its 8 corners, and each
// tests every triangle near the body (box_list.hpp); without them, the
// boxes' many points along their edges use the body's grid.
class TriangleHierarchy : public ::testing::TestWithParam<bool> {};

TEST_P(TriangleHierarchy, GivesTheLoopsTriangleContacts) {
  const bool edges = GetParam();
  Scene bvh(true, true, 0, nullptr, 16, edges), loop(true, true, std::numeric_limits<int>::max(), nullptr, 16, edges);
  long triangle_contacts = 0, edge_contacts = 0;
  std::map<std::string, int> per_body;
  for (int k = 0; k < 60; ++k) {
    bvh.bw.step();
    loop.bw.step();
    const std::string where = "step " + std::to_string(k);
    const xpbd::State& a = bvh.xw->state(bvh.cloth);
    ASSERT_NO_FATAL_FAILURE(expect_same_triangle_step(a, loop.xw->state(loop.cloth), where));
    for (const auto& c : a.triangle_contacts) ++per_body[bvh.body_name(bvh.cloth, c.body)];
    triangle_contacts += long(a.triangle_contacts.size());
    edge_contacts += long(a.edge_contacts.size());
  }
  // It means something only if features of several bodies, the spinning
  // one among them, met the triangles, and box edges met the cloth's edges
  // (the box edges' triangles come from the bodies' grids).
  std::printf("triangle contacts over 60 steps: %ld (box %d, hull %d, compound %d, spinner %d); edge contacts %ld\n",
              triangle_contacts, per_body["box"], per_body["hull"], per_body["compound"], per_body["spinner"],
              edge_contacts);
  EXPECT_EQ(edge_contacts > 0, edges);
  EXPECT_GT(per_body["box"], 0);
  EXPECT_GT(per_body["spinner"], 0);
  EXPECT_GT(per_body["compound"] + per_body["hull"], 0);
}

// The same under a body whose features are near most of the cloth: a tilted
// slab of 1.2 m x 1.2 m under the 1.4 m cloth (test_cloth) has about 400 of the 450
// triangles near its features. Its 8 corners (with the edge contacts) test
// them all; its points along the edges (without) are too many for that, and
// the triangles more than the 256 up to which they are sorted into a grid,
// so each feature queries the hierarchy itself.
TEST_P(TriangleHierarchy, GivesTheLoopsTriangleContactsUnderALargeBody) {
  const bool edges = GetParam();
  struct Slab {
    BulletWorld bw;
    std::unique_ptr<XpbdWorld> xw;
    xpbd_bullet::SystemId cloth;
    Slab(int bvh_from, bool edges) {
      bw.add_body(new btBoxShape(btVector3(Real(0.6), Real(0.03), Real(0.6))), 0,
                  pose(Vec3(0, Real(0.2), 0), btQuaternion(btVector3(1, 0, 1).normalized(), Real(0.1))));
      xw = std::make_unique<XpbdWorld>(bw.world());
      SystemSettings set;
      set.contacts.triangle_bvh_from = bvh_from;
      set.contacts.edge_contacts = edges;
      xpbd::SceneDesc scene;
      xpbd::add_cloth_grid(scene, test_cloth(true));
      System s = make_system(scene);
      cloth = xw->add_system(s.model, s.state, set);
    }
  };
  Slab bvh(0, edges), loop(std::numeric_limits<int>::max(), edges);
  long triangle_contacts = 0;
  for (int k = 0; k < 60; ++k) {
    bvh.bw.step();
    loop.bw.step();
    const std::string where = "step " + std::to_string(k);
    const xpbd::State& a = bvh.xw->state(bvh.cloth);
    ASSERT_NO_FATAL_FAILURE(expect_same_triangle_step(a, loop.xw->state(loop.cloth), where));
    triangle_contacts += long(a.triangle_contacts.size());
  }
  std::printf("triangle contacts over 60 steps: %ld\n", triangle_contacts);
  EXPECT_GT(triangle_contacts, 0);
}

INSTANTIATE_TEST_SUITE_P(WorldCulling, TriangleHierarchy, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "EdgeContacts" : "EdgePoints"; });

// The contact search runs over the threads of a system's pool, one
// candidate body at a time, and joins each candidate's contacts in
// candidate order: the particle and feature-triangle contacts, their order,
// the bodies' indices, the counts and so the steps are those of one thread,
// bit for bit, with 1, 2 or 4 threads (the hierarchy's grid and per-feature
// paths and the loop over all triangles alike). With the hierarchy the
// cloth is 48 x 48: 2,304 particles and 4,418 triangles, so that the pair
// search (1,024 particles a piece) and the triangles' boxes (2,048 a piece)
// are split too.
TEST(WorldCulling, ThreadsGiveTheSameContactsBitForBit) {
  for (const int bvh_from : {0, std::numeric_limits<int>::max()}) {
    const int n = bvh_from == 0 ? 48 : 16;
    xpbd::Workers pool1(1), pool2(2), pool4(4);
    // t1: one thread (the search runs in candidate order on the caller).
    Scene t1(true, true, bvh_from, &pool1, n), t2(true, true, bvh_from, &pool2, n),
        t4(true, true, bvh_from, &pool4, n);
    long contacts = 0, triangle_contacts = 0;
    for (int k = 0; k < 60; ++k) {
      for (Scene* sc : {&t1, &t2, &t4}) sc->bw.step();
      const std::string where = "bvh_from " + std::to_string(bvh_from) + ", step " + std::to_string(k);
      const auto& s1 = t1.xw->last_stats();
      for (Scene* sc : {&t2, &t4}) {
        const auto& sn = sc->xw->last_stats();
        ASSERT_TRUE(sn.contacts == s1.contacts && sn.queries == s1.queries &&
                    sn.triangle_contacts == s1.triangle_contacts && sn.shadows == s1.shadows &&
                    sn.swept_triangle_contacts == s1.swept_triangle_contacts &&
                    sn.capped_features == s1.capped_features)
            << where;
        for (xpbd_bullet::SystemId id : {t1.cloth, t1.shots}) {
          const xpbd::State& a = sc->xw->state(id);
          const xpbd::State& b = t1.xw->state(id);
          ASSERT_NO_FATAL_FAILURE(expect_same_contacts(a.contacts, b.contacts, where));
          ASSERT_NO_FATAL_FAILURE(expect_same_triangle_step(a, b, where));
        }
      }
      contacts += s1.contacts;
      triangle_contacts += s1.triangle_contacts;
    }
    // It means something only if both kinds of contact were found.
    EXPECT_GT(contacts, 0);
    EXPECT_GT(triangle_contacts, 0);
  }
}

// At the edge of the culling box. A particle at rest at distance d from a
// static box's top face, moving at u parallel to it (so the sweep misses),
// has reach = radius + thickness + margin + u dt, and query_point reports it
// iff d <= reach (closed form: the distance to a face is the height above
// it). The culling box is the body's AABB (here the box itself, axis-aligned)
// grown by the particle's half size radius + thickness + margin + |v| dt =
// reach, so d just below reach is at its very edge. Same check beside a
// sphere, whose AABB touches it only at the six axis points.
TEST(WorldCulling, ParticleJustWithinReachOfAnAabbFaceGetsItsContact) {
  BulletWorld bw(Vec3::Zero());
  const Vec3 half(Real(0.2), Real(0.1), Real(0.2));
  bw.add_static_box(half, BulletWorld::at(Vec3::Zero()));
  const Real R = Real(0.15);
  const Vec3 sphere_centre(2, 0, 0);
  bw.add_static_sphere(R, sphere_centre);
  XpbdWorld xw(bw.world());
  SystemSettings set;
  set.contacts.margin = Real(0.01);
  set.contacts.thickness = Real(0.005);
  const Real radius = Real(0.002);
  // 1e-3 relative either side of the boundary: far above round-off (at most
  // a few hundred eps relative in either build) and far below the margin.
  const Real below = Real(1) - Real(1e-3), above = Real(1) + Real(1e-3);
  struct Case {
    Vec3 x, v;
    bool contact;
  };
  std::vector<Case> cases;
  for (Real u : {Real(0), Real(0.3), Real(3)}) {  // m/s; 3 m/s: travel 5 cm > margin, the sweep path
    const Real reach = radius + set.contacts.thickness + set.contacts.margin + u * kDt;
    for (Real f : {below, above}) {
      cases.push_back({Vec3(Real(0.05), half.y() + f * reach, Real(-0.05)), Vec3(u, 0, 0), f < 1});
      cases.push_back({sphere_centre + Vec3(0, 0, R + f * reach), Vec3(0, u, 0), f < 1});
    }
  }
  xpbd::SceneDesc scene;
  for (const Case& c : cases) {
    scene.positions.push_back(c.x);
    scene.velocities.push_back(c.v);
    scene.masses.push_back(Real(0.1));
    scene.radii.push_back(radius);
  }
  System sys = make_system(scene);
  for (bool cull : {true, false}) {
    set.contacts.cull = cull;
    const auto id = xw.add_system(sys.model, sys.state, set);
    bw.step();
    std::vector<bool> got(cases.size(), false);
    for (const auto& c : xw.state(id).contacts) got[std::size_t(c.particle)] = true;
    for (std::size_t i = 0; i < cases.size(); ++i)
      EXPECT_EQ(got[i], cases[i].contact) << "cull " << cull << ", particle " << i;
    xw.remove_system(id);
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
