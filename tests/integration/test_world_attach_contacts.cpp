// A particle attached to a rigid body does not collide with that body
// (bullet_bridge/src/world.cpp, the contact loop). Without that exclusion a
// particle attached on the body's surface is pushed off it by the contact
// thickness (5 mm) at every substep while the attachment pulls it back: the
// stability sweep measured a constant 5.0-5.9 mm gap and extra explosions.
// The other particles of the same system still collide with the body.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

// A 1 kg box (half extent 5 cm) hangs from a 4-link rope pinned at the top;
// the rope's last particle is attached (compliance 0) at the centre of the
// box's top face. A loose particle of the same system is dropped onto that
// face 3 cm from the centre. After 2 s (at rest) the attached particle is
// at its point of the box -- within the solve's residual, far below the
// 5 mm thickness a contact would impose -- and the loose particle rests on
// the face at the contact thickness.
TEST(WorldAttachContacts, AttachedParticleIsNotPushedOffItsBody) {
  BulletWorld bw;
  const Real a = Real(0.05), spacing = Real(0.1);
  const int n = 5;
  const Vec3 top(0, 1, 0);
  const Vec3 box_centre = top - Vec3(0, spacing * Real(n - 1) + a, 0);
  btRigidBody* box = bw.add_body(new btBoxShape(btVector3(a, a, a)), 1, BulletWorld::at(box_centre));
  XpbdWorld xw(bw.world());

  xpbd::SceneDesc scene;
  xpbd::RopeDesc r;
  r.n = n;
  r.start = top;
  r.dir = -Vec3::UnitY();
  r.spacing = spacing;
  r.mass = Real(0.02);
  r.pin_first = true;
  const Index first = xpbd::add_rope(scene, r);
  const Index loose = scene.add_particle(box_centre + Vec3(Real(0.03), a + Real(0.02), 0), Real(0.01));
  System sys = make_system(scene);
  SystemSettings set;
  set.substeps = 20;
  set.iterations = 5;
  set.drag = 5;  // 1/s: settles within the 2 s
  ASSERT_TRUE(set.contacts.enabled);
  const Real thickness = set.contacts.thickness;
  const auto id = xw.add_system(sys.model, sys.state, set);
  const Index last = first + n - 1;
  xw.attach(id, last, box, btVector3(0, btScalar(a), 0));

  for (int k = 0; k < 120; ++k) bw.step();

  const btTransform& t = box->getCenterOfMassTransform();
  const btVector3 h = t * btVector3(0, btScalar(a), 0);
  const Vec3 hook(h.x(), h.y(), h.z());
  const xpbd::State& st = xw.state(id);
  // With contacts fighting the attachment the gap was the thickness (5 mm);
  // the attachment's own residual at 20 x 5 is orders of magnitude below
  // 0.5 mm (thickness / 10).
  EXPECT_LT((st.x[last] - hook).norm(), thickness / 10);
  // The loose particle rests on the top face at the thickness (the contact
  // still applies to the system's other particles): within 1 mm.
  const btVector3 l = t.inverse() * bt(st.x[loose]);
  const Vec3 local(l.x(), l.y(), l.z());
  EXPECT_NEAR(local.y() - a, thickness, Real(1e-3));
  EXPECT_LT(std::abs(local.x()), a);
  EXPECT_LT(std::abs(local.z()), a);
}

// A box lying on a cloth on the ground, the cloth's particles under its
// bottom face attached to it there (a tarp fastened under a crate): the
// ground holds those particles at the contact thickness, and the box rests
// on them, its bottom at the thickness (the attachments met). The attached
// particles have no contact with their own box, so the box is held only
// through the attachments: solved before the ground contacts, the
// attachments moved the light particles, not the box, and it hung up to
// 1.07 mm (2 kg) and 0.16 mm (20 kg) below them over the last second. Now the attachments join the
// particles' joint contact solve (xpbd/src/contact_block.cpp).
class WorldAttachOnGround : public ::testing::TestWithParam<int> {};

// With ContactSettings::surface_edge_contacts too: the cloth's edges at and
// next to the attached particles cross the box's bottom edges in the plane
// of its bottom face, and get edge contacts with the box with no thickness
// (world_edge_contacts.cpp), which do not lift it. (With the thickness, the
// box was lifted by 4 mm; it then got none.)
void box_rests_on_attached_particles(Real mass, bool surface_edges) {
  SystemSettings settings;
  settings.contacts.surface_edge_contacts = surface_edges;
  BulletWorld bw;
  bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
  const Real t = xpbd_bullet::ContactSettings{}.thickness;
  const Vec3 half(Real(0.15), Real(0.05), Real(0.15));
  const Vec3 centre(0, t + half.y(), 0);
  btRigidBody* box = bw.add_body(new btBoxShape(bt(half)), mass, BulletWorld::at(centre));
  XpbdWorld xw(bw.world());
  System sys = lying_cloth(1, 1, t);
  const auto id = xw.add_system(sys.model, sys.state, settings);
  int attached = 0;
  for (Index i = 0; i < sys.model->num_particles(); ++i) {
    const Vec3 x = sys.model->x0[std::size_t(i)];
    if (std::abs(x.x()) < half.x() && std::abs(x.z()) < half.z()) {
      xw.attach(id, i, box, bt(x - centre));
      ++attached;
    }
  }
  ASSERT_GT(attached, 10);
  Real worst = 0;  // the bottom's largest distance from t over the last second
  for (int f = 0; f < 120; ++f) {
    bw.step();
    ASSERT_EQ(xw.error(id), "");
    if (f >= 60) worst = std::max(worst, std::abs(Real(box->getCenterOfMassPosition().y()) - half.y() - t));
  }
  for (const Vec3& x : xw.state(id).x) EXPECT_GE(x.y(), t - Real(1e-4));
  // 1 % of the thickness: the solve's residual (measured 0.011-0.013 mm).
  EXPECT_LE(worst, Real(0.01) * t) << mass << " kg, surface edges " << surface_edges;
  if (surface_edges) {
    EXPECT_FALSE(xw.state(id).edge_contacts.empty()) << "no edge contact: the case is not tested";
  }
}

TEST_P(WorldAttachOnGround, BoxRestsOnTheParticlesAttachedUnderIt) {
  box_rests_on_attached_particles(Real(GetParam()), false);
  box_rests_on_attached_particles(Real(GetParam()), true);
}

INSTANTIATE_TEST_SUITE_P(Mass, WorldAttachOnGround, ::testing::Values(2, 20));

// A cloth corner fastened on a bar and falling over the bar's edge: one
// triangle (no collision triangles), its particle 0 attached to the centre
// of a static bar's top face (half extents 0.3 x 0.03 x 0.03 m), its
// particles 1 and 2 (x = -+2 cm) just above the top face's level beyond
// the bar's side (z = 0.04). They fall. The particle contacts keep
// particles out of the bar, not edges: without edge contacts the two come
// to rest on the side face, 2 cm below the top, and the edges 0-1 and 0-2
// cut 1 cm deep through the bar's top edge (y = z = 0.03). With surface edge
// contacts those edges, at a particle attached to the bar, get contacts
// with the bar's edges with no thickness (world_edge_contacts.cpp) and stay
// clear of the bar, at their rest length, particle 0 at its attachment.
// (Before, edges at an attached particle got no contact with its body: in
// the squeeze application the cloth wrapped round its bar with edges
// through it; docs/squeeze.md.)
TEST(WorldAttachContacts, EdgesAtAnAttachedParticleAreKeptOutOfItsBody) {
  const Vec3 half(Real(0.3), Real(0.03), Real(0.03));
  const auto run = [&](bool surface_edges) {
    BulletWorld bw;
    btRigidBody* bar = bw.add_body(new btBoxShape(bt(half)), 0, BulletWorld::at(Vec3::Zero()));
    XpbdWorld xw(bw.world());
    xpbd::SceneDesc scene;
    scene.add_particle(Vec3(0, half.y(), 0), Real(0.01));
    scene.add_particle(Vec3(Real(-0.02), half.y() + Real(0.001), Real(0.04)), Real(0.01));
    scene.add_particle(Vec3(Real(0.02), half.y() + Real(0.001), Real(0.04)), Real(0.01));
    for (auto [a, b] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 2}})
      scene.distances.push_back(xpbd::DistanceDesc{a, b, std::nullopt, {}});
    scene.surface_triangles = {{0, 1, 2}};
    System sys = make_system(scene);
    SystemSettings set;
    set.contacts.surface_edge_contacts = surface_edges;
    const auto id = xw.add_system(sys.model, sys.state, set);
    xw.attach(id, 0, bar, btVector3(0, btScalar(half.y()), 0));
    for (int f = 0; f < 60; ++f) bw.step();
    return xw.state(id).x;
  };
  // The deepest point of edge 0-k inside the bar (> 0: inside), sampled.
  const auto depth = [&](const std::vector<Vec3>& x, int k) {
    Real worst = -1;
    for (int i = 1; i < 20; ++i) {
      const Vec3 p = x[0] + (x[std::size_t(k)] - x[0]) * (Real(i) / 20);
      worst = std::max(worst, (half - p.cwiseAbs()).minCoeff());
    }
    return worst;
  };
  const std::vector<Vec3> off = run(false), on = run(true);
  std::printf("edges at an attached particle: without surface edges the deepest points %.4g, %.4g m inside the bar; "
              "with them %.4g, %.4g m (particle 1 at y %.4g, z %.4g)\n",
              double(depth(off, 1)), double(depth(off, 2)), double(depth(on, 1)), double(depth(on, 2)),
              double(on[1].y()), double(on[1].z()));
  EXPECT_GT(depth(off, 1), Real(0.005));  // the control: through the bar
  EXPECT_GT(depth(off, 2), Real(0.005));
  const Real rest = std::sqrt(Real(0.02 * 0.02 + 0.04 * 0.04 + 0.001 * 0.001));
  for (int k : {1, 2}) {
    EXPECT_LE(depth(on, k), Real(1e-4)) << "edge 0-" << k;
    EXPECT_NEAR((on[std::size_t(k)] - on[0]).norm(), rest, Real(1e-3)) << "edge 0-" << k << " at its rest length";
  }
  EXPECT_NEAR((on[0] - Vec3(0, half.y(), 0)).norm(), 0, Real(1e-4));  // still at its attachment
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
