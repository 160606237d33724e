// Per-particle masses and an initial velocity in the cloth and rope
// generators (xpbd::ClothGridDesc / RopeDesc particle_masses and velocity;
// scene files: soft.generators[].cloth|rope.particle_masses, velocity): a
// heavy end or a thrown cloth without an explicit particle list. Checked
// against the values given, through a scene file round trip, and in flight:
// with no gravity and every particle moving at the same velocity, nothing
// stretches and the cloth moves rigidly by v t.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "demos/scene_runner.hpp"
#include "support/scene_compare.hpp"
#include "xpbd/error.hpp"

namespace xpbd_demos {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;

SceneSpec thrown() {
  SceneSpec s;
  s.name = "thrown";
  s.solver.gravity = Vec3::Zero();
  s.solver.frames = 30;
  xpbd::RopeDesc r;
  r.n = 5;
  r.start = Vec3(0, 2, 0);
  r.dir = Vec3::UnitX();
  r.spacing = Real(0.1);
  r.mass = Real(0.01);
  r.pin_first = true;
  r.particle_masses = {{4, 0, 2}};  // a heavy end
  s.soft.generators.push_back(r);
  xpbd::ClothGridDesc c;
  c.nx = c.ny = 4;
  c.mass = Real(1.6);  // 0.1 kg each
  c.origin = Vec3(0, 5, 0);
  c.velocity = Vec3(1, Real(0.5), -2);
  c.particle_masses = {{3, 3, Real(0.4)}, {0, 1, Real(0.3)}};
  s.soft.generators.push_back(c);
  return s;
}

TEST(GeneratorMasses, MassesAndVelocityAreTheOnesGivenAndRoundTrip) {
  const SceneSpec s = thrown();
  test::round_trip(s);  // the file gives back the same model
  const ExpandedSoft soft = expand(s.soft, s.base_dir);
  const auto& x = soft.scene;
  ASSERT_EQ(x.positions.size(), 5u + 16u);
  EXPECT_EQ(x.masses[0], Real(0));       // the rope's pinned first particle
  EXPECT_EQ(x.masses[1], Real(0.01));
  EXPECT_EQ(x.masses[4], Real(2));       // its heavy end
  EXPECT_EQ(x.velocities[4], Vec3::Zero());
  const std::size_t c0 = 5;  // the cloth's first particle; (i, j) is c0 + j * 4 + i
  EXPECT_EQ(x.masses[c0 + 3 * 4 + 3], Real(0.4));
  EXPECT_EQ(x.masses[c0 + 1 * 4 + 0], Real(0.3));
  EXPECT_EQ(x.masses[c0 + 1], Real(0.1));
  for (std::size_t k = c0; k < x.positions.size(); ++k) EXPECT_EQ(x.velocities[k], Vec3(1, Real(0.5), -2));
}

TEST(GeneratorMasses, ThrownClothMovesRigidly) {
  SceneSpec s = thrown();
  s.soft.generators.erase(s.soft.generators.begin());  // the cloth alone
  const RunResult r = run_scene(s, run_options(s));
  ASSERT_TRUE(r.finite);
  // Uniform translation keeps every edge at its rest length.
  EXPECT_LT(r.max_strain, 64 * std::numeric_limits<Real>::epsilon());
  // Kinetic energy 1/2 M |v|^2, M = 0.1 x 14 + 0.4 + 0.3 = 2.1 kg, |v|^2 = 5.25.
  // Round-off: v = (x - x_prev)/h every substep, eps |x| / h with |x| ~ 5 m
  // and h = 1/600 s: 3.6e-4 m/s in float (relative 2e-3 of the energy is
  // ample), 1e-12 in double.
  const double ke = 0.5 * 2.1 * 5.25;
  EXPECT_NEAR(r.series.back().kinetic_energy, ke, ke * (sizeof(Real) == 4 ? 2e-3 : 1e-9));
}

TEST(GeneratorMasses, BadEntriesNameTheGeneratorAndEntry) {
  auto error = [](const xpbd::RopeDesc& r) {
    xpbd::SceneDesc s;
    try {
      xpbd::add_rope(s, r);
    } catch (const xpbd::SceneError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  xpbd::RopeDesc r;
  r.n = 5;
  r.particle_masses = {{5, 0, 1}};
  EXPECT_NE(error(r).find("rope.particle_masses[0]: particle 5 is outside [0, 5)"), std::string::npos) << error(r);
  r.particle_masses = {{0, 0, 1}};
  EXPECT_NE(error(r).find("pinned"), std::string::npos) << error(r);
  r.particle_masses = {{2, 0, std::numeric_limits<Real>::quiet_NaN()}};
  EXPECT_NE(error(r).find("mass must be finite and > 0"), std::string::npos) << error(r);
  r.particle_masses = {};
  r.velocity = Vec3(std::numeric_limits<Real>::infinity(), 0, 0);
  EXPECT_NE(error(r).find("rope.velocity"), std::string::npos) << error(r);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd_demos
