// The box edge - soft edge search (bullet_bridge/src/world_edge_contacts.cpp)
// against a closed form: a flat cloth 1 mm above a box's top face, turned
// so that no cloth edge is parallel to a box edge. A soft edge and a top
// edge of the box then have their closest points on both edges exactly
// when they cross seen from above, 1 mm apart; every other pair has its
// closest points off one of the two edges, and the box's other eight edges
// are 0.1 m below or end below the cloth. So the contacts must be the
// crossing pairs, each once, and no other. The crossings are counted here
// from the cloth's own triangles with a 2D segment test, not with the
// search's code; the search is run through each of its three paths: the
// collision triangles with the hierarchy, the same with the loop over
// every triangle, and the surface triangles' edges
// (ContactSettings::surface_edge_contacts).
#include <gtest/gtest.h>

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "xpbd/xpbd.hpp"
#include "xpbd_bullet/world.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;

enum class Path { hierarchy, loop, surface };

// Which side of the line through a, b (seen from above: x, z) point p is on.
double side(const Vec3& a, const Vec3& b, const Vec3& p) {
  return double(b.x() - a.x()) * double(p.z() - a.z()) - double(b.z() - a.z()) * double(p.x() - a.x());
}

// Segments ab and cd cross seen from above, each one's ends strictly on
// both sides of the other's line.
bool cross(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0;
}

class EdgeSearch : public ::testing::TestWithParam<Path> {};

TEST_P(EdgeSearch, FindsEveryCrossingPairAndNoOther) {
  const Path path = GetParam();
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
  world.setGravity(btVector3(0, 0, 0));
  const Vec3 half(Real(0.1), Real(0.05), Real(0.07));
  btBoxShape shape(btVector3(half.x(), half.y(), half.z()));
  btTransform pose(btQuaternion(btVector3(0, 1, 0), btScalar(0.35)), btVector3(btScalar(0.013), 0, btScalar(-0.021)));
  btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, &shape);
  info.m_startWorldTransform = pose;
  btRigidBody box(info);
  world.addRigidBody(&box);

  // 24 x 24 particles over 0.6 m (2.6 cm apart), 1 mm above the top face.
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc d;
  d.nx = d.ny = 24;
  d.size_u = d.size_v = Real(0.6);
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  d.origin = Vec3(Real(-0.3), half.y() + Real(0.001), Real(-0.3));
  d.collision_triangles = path != Path::surface;
  xpbd::add_cloth_grid(scene, d);
  // The triangles in a shuffled order, each starting at a random corner: on
  // the grid's own order, which triangle meets an edge first follows a
  // pattern that hides a mix-up of a triangle's sides.
  std::mt19937 rng(11);
  for (auto* list : {&scene.collision_triangles, &scene.surface_triangles}) {
    std::shuffle(list->begin(), list->end(), rng);
    for (auto& t : *list) std::rotate(t.begin(), t.begin() + std::ptrdiff_t(rng() % 3), t.end());
  }
  const auto model = std::make_shared<xpbd::Model>(xpbd::compile(scene));
  const auto& tris = path == Path::surface ? model->surface_triangles : model->collision_triangles;
  ASSERT_FALSE(tris.empty());

  xpbd_bullet::XpbdWorld xw(world);
  xpbd_bullet::SystemSettings set;
  set.contacts.edge_contacts = true;
  set.contacts.surface_edge_contacts = path == Path::surface;
  set.contacts.triangle_bvh_from = path == Path::loop ? std::numeric_limits<int>::max() : 0;
  const auto id = xw.add_system(model, xpbd::make_state(*model), set);
  xw.pre_solve(Real(1) / Real(60));  // the contacts of the step's start
  const auto& found = xw.state(id).edge_contacts;

  // The box's four top edges (body frame; world: at the pose).
  const std::array<std::array<Vec3, 2>, 4> top{{
      {Vec3(-half.x(), half.y(), half.z()), Vec3(half.x(), half.y(), half.z())},
      {Vec3(-half.x(), half.y(), -half.z()), Vec3(half.x(), half.y(), -half.z())},
      {Vec3(half.x(), half.y(), -half.z()), Vec3(half.x(), half.y(), half.z())},
      {Vec3(-half.x(), half.y(), -half.z()), Vec3(-half.x(), half.y(), half.z())},
  }};
  const auto world_of = [&](const Vec3& local) {
    const btVector3 w = pose * btVector3(local.x(), local.y(), local.z());
    return Vec3(w.x(), w.y(), w.z());
  };
  // The cloth's edges, each once.
  std::set<std::pair<xpbd::Index, xpbd::Index>> edges;
  for (const auto& t : tris)
    for (int i = 0; i < 3; ++i) {
      const xpbd::Index a = t[std::size_t(i)], b = t[std::size_t((i + 1) % 3)];
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  // The crossing pairs: (top edge, soft edge).
  std::set<std::tuple<int, xpbd::Index, xpbd::Index>> want;
  const auto& x = xw.state(id).x;
  for (int k = 0; k < 4; ++k)
    for (const auto& [a, b] : edges)
      if (cross(world_of(top[std::size_t(k)][0]), world_of(top[std::size_t(k)][1]), x[a], x[b])) want.insert({k, a, b});
  ASSERT_GT(want.size(), 40u);  // three edge directions cross each of the four

  // The contacts found: each on a top edge, each pair once.
  std::set<std::tuple<int, xpbd::Index, xpbd::Index>> got;
  for (const xpbd::BodyEdgeContact& c : found) {
    int k = -1;
    for (int j = 0; j < 4; ++j) {
      const auto& [e0, e1] = top[std::size_t(j)];
      if (((c.a - e0).norm() < Real(1e-6) && (c.b - e1).norm() < Real(1e-6)) ||
          ((c.a - e1).norm() < Real(1e-6) && (c.b - e0).norm() < Real(1e-6)))
        k = j;
    }
    EXPECT_GE(k, 0) << "a contact on a box edge that is not a top edge: " << c.a.transpose() << " - "
                    << c.b.transpose();
    const auto pair = std::make_tuple(k, std::min(c.p[0], c.p[1]), std::max(c.p[0], c.p[1]));
    EXPECT_TRUE(got.insert(pair).second) << "pair found twice: top edge " << k << ", particles " << c.p[0] << ", "
                                         << c.p[1];
  }
  for (const auto& [k, a, b] : want)
    EXPECT_TRUE(got.count({k, a, b})) << "missed: top edge " << k << ", particles " << a << ", " << b;
  for (const auto& [k, a, b] : got)
    EXPECT_TRUE(want.count({k, a, b})) << "not crossing: top edge " << k << ", particles " << a << ", " << b;
  world.removeRigidBody(&box);
}

INSTANTIATE_TEST_SUITE_P(WorldEdgeContacts, EdgeSearch,
                         ::testing::Values(Path::hierarchy, Path::loop, Path::surface),
                         [](const ::testing::TestParamInfo<Path>& p) {
                           return std::string(p.param == Path::hierarchy ? "Hierarchy"
                                              : p.param == Path::loop    ? "Loop"
                                                                         : "SurfaceEdges");
                         });

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
