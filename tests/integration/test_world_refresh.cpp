// ContactSettings::refresh (world_refresh.cpp): a particle at rest at the
// start of a step, with no contact, is yanked by its edge through a static
// box it was 0.2 m from. Its contacts were searched along its straight path
// (it was at rest: 1.5 cm around it); the refresh queries it again in the
// substep it leaves that path, and the box stops it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <utility>
#include <vector>

#include "support.hpp"
#include "xpbd_bullet/narrowphase.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

namespace {

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

struct Result {
  Real deepest = 0;  // m, deepest B centre inside the box over the run
  Real first_x = 0;  // m, B's x after the first step
  int refreshed = 0;
};

// A at (1, 0.85, 0) moving +x at 30 m/s (0.5 m per 60 Hz step), B 1 m
// behind it at rest, joined by a stiff edge; no gravity. The box spans x in
// [0.2, 0.3], y in [0.75, 0.95], between them: A moves away from it (and is
// farther from it than its search reaches), B is dragged into it.
Result run(bool refresh) {
  BulletWorld bw(Vec3::Zero());
  const btRigidBody* box =
      bw.add_static_box(Vec3(0.05, 0.1, 0.5), BulletWorld::at(Vec3(0.25, 0.85, 0)), 0);
  XpbdWorld xw(bw.world());
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3(1, 0.85, 0), Real(0.1));
  scene.add_particle(Vec3(0, 0.85, 0), Real(0.1));
  scene.distances.push_back(xpbd::DistanceDesc{0, 1, std::nullopt, {}});
  System sys = make_system(scene);
  sys.state.v[0] = Vec3(30, 0, 0);
  SystemSettings set;
  set.contacts.refresh = refresh;
  const xpbd_bullet::SystemId id = xw.add_system(sys.model, sys.state, set);
  Result r;
  for (int f = 0; f < 3; ++f) {
    bw.step();
    r.refreshed += xw.last_stats().refreshed;
    if (f == 0) r.first_x = xw.state(id).x[1].x();
    xpbd_bullet::ParticleContact pc;
    if (xpbd_bullet::query_point(*box, xw.state(id).x[1], 0, pc)) r.deepest = std::max(r.deepest, -pc.distance);
  }
  return r;
}

TEST(WorldRefresh, ParticleYankedThroughABoxIsStoppedByIt) {
  const Result off = run(false), on = run(true);
  std::printf("B yanked towards a box 0.2 m away: without the refresh %.4g m deep, at x = %.4g m after "
              "the first step; with it %.4g m deep, at x = %.4g m, %d particle queries again\n",
              double(off.deepest), double(off.first_x), double(on.deepest), double(on.first_x), on.refreshed);
  // Without the refresh B ends the first step inside the box.
  EXPECT_EQ(off.refreshed, 0);
  EXPECT_GT(off.deepest, Real(0.01));
  // With it, B stops at the box's face, the contact thickness before it
  // (x = 0.2 - 0.005 m), and is never inside.
  EXPECT_GT(on.refreshed, 0);
  EXPECT_NEAR(on.first_x, Real(0.2) - xpbd_bullet::ContactSettings{}.thickness, Real(1e-4));
  EXPECT_EQ(on.deepest, Real(0));
}

}  // namespace

namespace {

// A refreshed particle that already has a contact with the body gets that
// contact replaced, not a second one: a pair solved twice per sweep gets
// twice the normal and friction correction. A 10 kg ball dropped at 3 m/s
// onto a membrane pinned at its corners carries the particles under it off
// their paths (the refresh queries them again) while they keep their
// contact with it. After every step each (particle, body) pair has at most
// one contact. (Before the fix this run had 453 pairs twice.)
TEST(WorldRefresh, RefreshedPairKeepsOneContact) {
  BulletWorld bw;
  const Real radius = Real(0.15);
  bw.add_body(new btSphereShape(radius), 10, BulletWorld::at(Vec3(0, radius + Real(0.011), 0)),
              Vec3(0, -3, 0));
  XpbdWorld xw(bw.world());
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc c;
  c.nx = c.ny = 21;
  c.size_u = c.size_v = 1;
  c.mass = Real(0.2);
  c.origin = Vec3(Real(-0.5), 0, Real(-0.5));
  c.u = Vec3::UnitX();
  c.v = Vec3::UnitZ();
  c.pins = xpbd::ClothPins::all_corners;
  xpbd::add_cloth_grid(scene, c);
  System sys = make_system(scene);
  const xpbd_bullet::SystemId id = xw.add_system(sys.model, sys.state);
  int refreshed = 0, duplicated = 0;
  std::vector<std::pair<Index, Index>> pairs;
  for (int f = 0; f < 30; ++f) {
    bw.step();
    refreshed += xw.last_stats().refreshed;
    pairs.clear();
    for (const xpbd::BodyContact& k : xw.state(id).contacts) pairs.emplace_back(k.particle, k.body);
    std::sort(pairs.begin(), pairs.end());
    duplicated += int(pairs.end() - std::unique(pairs.begin(), pairs.end()));
  }
  std::printf("ball on a membrane, 30 frames: %d particles queried again, %d duplicate contacts\n", refreshed,
              duplicated);
  EXPECT_GT(refreshed, 0);
  EXPECT_EQ(duplicated, 0);
}

}  // namespace

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
