// A bound on the contacts of one rigid feature (issue 14, bounded
// resources): a feature gets at most 16 feature-triangle contacts per step
// (the first found), and StepStats::capped_features counts the features
// that reached the bound. A fuzzed scene with a 5 m contact thickness made
// 470,000 contacts per step (every feature of a 10 m box with every
// triangle of a crumpled cloth).
//
// Scene (no gravity, one step): 20 square cloths of 2 x 2 particles, 0.4 m
// wide, stacked 2 mm apart over the top face of a static 0.2 m box, in one
// system with collision triangles and a 5 cm thickness. Each top corner
// and top edge point of the box lies under both triangles or one triangle
// of every layer, all within reach: 20 to 40 contacts each without the
// bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <tuple>

#include "../integration/support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

TEST(WorldFeatureCap, AtMostSixteenTriangleContactsPerFeature) {
  BulletWorld bw(Vec3::Zero());
  bw.add_static_box(Vec3::Constant(Real(0.1)), BulletWorld::at(Vec3::Zero()));
  XpbdWorld xw(bw.world());
  xpbd::SceneDesc scene;
  constexpr int kLayers = 20;
  for (int k = 0; k < kLayers; ++k) {
    xpbd::ClothGridDesc d;
    d.nx = d.ny = 2;
    d.size_u = d.size_v = Real(0.4);
    d.u = Vec3::UnitX();
    d.v = Vec3::UnitZ();
    d.origin = Vec3(Real(-0.2), Real(0.102) + Real(0.002) * Real(k), Real(-0.2));
    d.mass = Real(0.01);
    d.collision_triangles = true;
    xpbd::add_cloth_grid(scene, d);
  }
  System s = make_system(scene);
  SystemSettings set;
  set.contacts.thickness = Real(0.05);
  const auto id = xw.add_system(s.model, s.state, set);
  bw.step();
  const auto& stats = xw.last_stats();
  const auto& contacts = xw.state(id).triangle_contacts;
  std::map<std::tuple<Real, Real, Real>, int> per_feature;
  for (const auto& c : contacts) ++per_feature[{c.r.x(), c.r.y(), c.r.z()}];
  int most = 0;
  for (const auto& [r, n] : per_feature) most = std::max(most, n);
  int at_bound = 0;
  for (const auto& [r, n] : per_feature) at_bound += n == 16;
  std::printf("%zu features with contacts, %zu contacts, at most %d per feature, %d capped\n", per_feature.size(),
              contacts.size(), most, stats.capped_features);
  EXPECT_EQ(most, 16);
  EXPECT_EQ(stats.capped_features, at_bound);
  EXPECT_EQ(stats.triangle_contacts, static_cast<int>(contacts.size()));
  // Every top corner and top edge point is under every layer: at least 20
  // candidates each, so each one keeps exactly 16.
  for (const auto& [r, n] : per_feature) {
    if (std::get<1>(r) > Real(0.09)) {
      EXPECT_EQ(n, 16);
    }
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
