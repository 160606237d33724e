// Materials changed at run time (XpbdWorld::set_material, xpbd/materials.hpp):
// a 1 kg particle on a spring (one Distance element) to a kinematic particle,
// no gravity, oscillates with the closed-form period T = 2 pi sqrt(m alpha)
// before and after its compliance alpha is changed, in one system that keeps
// its id; the application's own model keeps the old material.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

constexpr Real kMass = 1;        // kg
constexpr Real kRest = Real(0.1);  // m

// Mean period (s) of the upward zero crossings of samples (x - rest) taken
// every dt, from the first crossing on (linear interpolation between samples).
Real mean_period(const std::vector<Real>& u, Real dt) {
  std::vector<Real> t;
  for (std::size_t k = 1; k < u.size(); ++k)
    if (u[k - 1] < 0 && u[k] >= 0) t.push_back(dt * (Real(k - 1) + u[k - 1] / (u[k - 1] - u[k])));
  if (t.size() < 3) return -1;
  return (t.back() - t.front()) / Real(t.size() - 1);
}

TEST(WorldMaterials, SpringPeriodFollowsTheComplianceSetAtRunTime) {
  BulletWorld bw(Vec3::Zero());  // no gravity
  XpbdWorld xw(bw.world());
  const Real pi = std::acos(Real(-1));
  const Real period1 = Real(0.5), period2 = Real(1);  // s
  const Real alpha1 = (period1 / (2 * pi)) * (period1 / (2 * pi)) / kMass;  // m/N
  const Real alpha2 = (period2 / (2 * pi)) * (period2 / (2 * pi)) / kMass;
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3::Zero(), 0);                    // kinematic anchor
  scene.add_particle(Vec3(kRest + Real(0.01), 0, 0), kMass);  // 1 cm out
  xpbd::DistanceDesc d;
  d.a = 0;
  d.b = 1;
  d.rest = kRest;
  d.mat.compliance = alpha1;
  scene.distances.push_back(d);
  System s = make_system(scene);
  SystemSettings set;
  set.substeps = 20;  // omega h = 0.01 at the shorter period: its error is O(1e-4)
  const auto id = xw.add_system(s.model, s.state, set);

  std::vector<Real> u;
  for (int k = 0; k < 180; ++k) {  // 3 s: 6 periods
    bw.step();
    u.push_back(xw.state(id).x[1].x() - kRest);
  }
  const Real t1 = mean_period(u, kDt);

  xw.set_material<xpbd::Distance>(id, 0, 1, xpbd::Material{alpha2, 0});
  u.clear();
  for (int k = 0; k < 360; ++k) {  // 6 s: 6 periods
    bw.step();
    u.push_back(xw.state(id).x[1].x() - kRest);
  }
  const Real t2 = mean_period(u, kDt);
  std::printf("spring period %.5f s (closed form %.5f), after the change %.5f s (%.5f)\n", double(t1),
              double(period1), double(t2), double(period2));
  EXPECT_NEAR(t1, period1, Real(0.01) * period1);
  EXPECT_NEAR(t2, period2, Real(0.01) * period2);
  EXPECT_TRUE(xw.has_system(id));
  EXPECT_EQ(xw.model(id).get<xpbd::Distance>()[0].mat.compliance, alpha2);
  EXPECT_EQ(s.model->get<xpbd::Distance>()[0].mat.compliance, alpha1);  // the application's copy
}

TEST(WorldMaterials, BadChangesAreRefusedAndChangeNothing) {
  BulletWorld bw;
  XpbdWorld xw(bw.world());
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc c;
  c.nx = c.ny = 4;
  xpbd::add_cloth_grid(scene, c);
  System s = make_system(scene);
  const auto id = xw.add_system(s.model, s.state);
  const std::size_t n = xw.model(id).get<xpbd::Distance>().size();
  const xpbd::Material before = xw.model(id).get<xpbd::Distance>()[0].mat;
  auto message = [&](auto f) {
    try {
      f();
    } catch (const xpbd::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string range = message([&] { xw.set_material<xpbd::Distance>(id, n - 1, 2, {}); });
  EXPECT_NE(range.find("set_material<distance>"), std::string::npos) << range;
  EXPECT_NE(range.find(std::to_string(n)), std::string::npos) << range;
  const std::string neg = message([&] { xw.set_material<xpbd::Distance>(id, 0, 1, {Real(-1), 0}); });
  EXPECT_NE(neg.find("mat.compliance"), std::string::npos) << neg;
  EXPECT_NE(neg.find("-1"), std::string::npos) << neg;
  EXPECT_THROW(xw.set_material<xpbd::Distance>(xpbd_bullet::SystemId(77), 0, 1, {}), std::out_of_range);
  EXPECT_EQ(xw.model(id).get<xpbd::Distance>()[0].mat.compliance, before.compliance);
  // Damping switches the damped kernel on (Model::has_damping), and the
  // coloured copy of the Distance elements follows.
  xw.set_material<xpbd::Distance>(id, 0, n, {Real(1e-4), Real(2)});
  EXPECT_TRUE(xw.model(id).has_damping[xpbd::type_index_v<xpbd::Distance>]);
  for (const xpbd::Distance& e : xw.model(id).distance_by_colour) EXPECT_EQ(e.mat.damping, Real(2));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
