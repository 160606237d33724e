// XpbdWorld::debugDraw through Bullet's debug drawer: one line per distance
// edge (or per collision-triangle edge when there are none), and each
// particle-body contact of the last step as a contact point.
#include <gtest/gtest.h>

#include <LinearMath/btIDebugDraw.h>

#include "support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::XpbdWorld;

// Records what it is asked to draw.
struct Recorder : btIDebugDraw {
  int mode = DBG_DrawWireframe;
  std::vector<std::pair<btVector3, btVector3>> lines;
  std::vector<btVector3> line_colours;
  std::vector<btScalar> contact_distances;
  std::vector<btVector3> contact_normals;
  void drawLine(const btVector3& a, const btVector3& b, const btVector3& c) override {
    lines.emplace_back(a, b);
    line_colours.push_back(c);
  }
  void drawContactPoint(const btVector3&, const btVector3& n, btScalar d, int, const btVector3&) override {
    contact_normals.push_back(n);
    contact_distances.push_back(d);
  }
  void reportErrorWarning(const char*) override {}
  void draw3dText(const btVector3&, const char*) override {}
  void setDebugMode(int m) override { mode = m; }
  int getDebugMode() const override { return mode; }
};

// An nx x ny grid cloth lying flat at height y, structural edges only (or
// no edges at all, only its triangles).
System grid(int nx, int ny, Real y, bool edges) {
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc c;
  c.nx = nx;
  c.ny = ny;
  c.size_u = c.size_v = Real(0.5);
  c.origin = Vec3(-0.25, y, -0.25);
  c.u = Vec3::UnitX();
  c.v = Vec3::UnitZ();
  c.mass = Real(0.1);
  c.shear = false;
  c.bend_distance = false;
  c.collision_triangles = !edges;
  xpbd::add_cloth_grid(scene, c);
  if (!edges) scene.distances.clear();
  return make_system(scene);
}

// Does segment (a, b) join particles i and j of x, in either direction?
bool joins(const std::pair<btVector3, btVector3>& l, const Vec3& a, const Vec3& b) {
  return (vec(l.first) == a && vec(l.second) == b) || (vec(l.first) == b && vec(l.second) == a);
}

TEST(WorldDebugDraw, OneLinePerStructuralEdgeThroughTheWorldsDrawer) {
  BulletWorld bw;
  XpbdWorld xw(bw.world());
  const int nx = 5, ny = 4;
  System s = grid(nx, ny, 1, true);
  const auto id = xw.add_system(s.model, s.state);
  Recorder rec;
  bw.world().setDebugDrawer(&rec);
  bw.world().debugDrawWorld();  // Bullet calls the actions' debugDraw
  // (nx - 1) ny horizontal plus nx (ny - 1) vertical edges.
  ASSERT_EQ(rec.lines.size(), std::size_t((nx - 1) * ny + nx * (ny - 1)));
  const xpbd::State& st = xw.state(id);
  for (const xpbd::Distance& d : xw.model(id).get<xpbd::Distance>()) {
    const Vec3 a = st.x[d.p[0]], b = st.x[d.p[1]];
    EXPECT_TRUE(std::any_of(rec.lines.begin(), rec.lines.end(), [&](auto& l) { return joins(l, a, b); }));
  }
  for (const btVector3& c : rec.line_colours) EXPECT_EQ(c, rec.getDefaultColors().m_activeObject);
  bw.world().setDebugDrawer(nullptr);
}

TEST(WorldDebugDraw, TriangleEdgesWhenThereAreNoDistanceEdges) {
  BulletWorld bw;
  XpbdWorld xw(bw.world());
  const int nx = 3, ny = 3;
  System s = grid(nx, ny, 1, false);
  ASSERT_TRUE(s.model->get<xpbd::Distance>().empty());
  xw.add_system(s.model, s.state);
  Recorder rec;
  xw.debugDraw(&rec);
  // 2 (nx - 1)(ny - 1) triangles, three lines each.
  EXPECT_EQ(rec.lines.size(), std::size_t(3 * 2 * (nx - 1) * (ny - 1)));
}

TEST(WorldDebugDraw, ContactsOfAClothRestingOnTheGround) {
  BulletWorld bw;
  bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
  XpbdWorld xw(bw.world());
  System s = grid(4, 4, Real(0.05), true);
  const auto id = xw.add_system(s.model, s.state);
  for (int k = 0; k < 60; ++k) bw.step();
  Recorder rec;
  rec.mode = btIDebugDraw::DBG_DrawContactPoints;  // contacts only: no lines
  xw.debugDraw(&rec);
  EXPECT_TRUE(rec.lines.empty());
  const std::size_t contacts = xw.state(id).contacts.size();
  ASSERT_EQ(contacts, 16u);  // every particle lies on the plane
  ASSERT_EQ(rec.contact_distances.size(), contacts);
  // At rest each particle is at the thickness above the ground (the contact
  // is solved to C = 0 every substep), less what gravity adds in one
  // substep, g h^2; the normal is the plane's.
  const Real t = xpbd_bullet::SystemSettings{}.contacts.thickness;
  const Real h = kDt / Real(xpbd_bullet::SystemSettings{}.substeps);
  for (std::size_t k = 0; k < contacts; ++k) {
    EXPECT_NEAR(rec.contact_distances[k], t, kG * h * h + 1e-9);
    EXPECT_NEAR(rec.contact_normals[k].y(), 1, 1e-9);
  }
  rec.mode = 0;  // nothing asked for: nothing drawn
  rec.contact_distances.clear();
  xw.debugDraw(&rec);
  EXPECT_TRUE(rec.lines.empty() && rec.contact_distances.empty());
  xw.debugDraw(nullptr);  // no drawer: nothing happens
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
