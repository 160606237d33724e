// compile() input checks (compile.cpp): every invalid input is rejected with a
// SceneError whose message names the element (array and index), the field and
// the offending value. The scenes are valid except for the one field under
// test, so each test also shows that the check is specific.
#include <gtest/gtest.h>

#include <limits>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::scene_error_names;

constexpr Real kInf = std::numeric_limits<Real>::infinity();
constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();

// Four particles on the x axis, radius 0.1, a valid distance, collision, pin
// and plane. compile() must accept it.
SceneDesc valid_scene() {
  SceneDesc s;
  for (int i = 0; i < 4; ++i) s.add_particle(Vec3(Real(i), 1, 0), 1, Real(0.1));
  s.distances.push_back(DistanceDesc{0, 1, std::nullopt, {}});
  s.distances.push_back(DistanceDesc{1, 2, Real(1), {}});
  s.collisions.push_back(CollisionDesc{0, 3, {}});
  s.pins.push_back(PinDesc{0, std::nullopt, {}});
  s.planes.push_back(PlaneDesc{Vec3::UnitY(), 0, {}});
  return s;
}

TEST(Compile, ValidSceneIsAccepted) {
  const Model m = compile(valid_scene());
  EXPECT_EQ(m.num_particles(), 4);
  EXPECT_EQ(m.get<Distance>().size(), 2u);
  EXPECT_EQ(m.get<Collision>().size(), 1u);
  EXPECT_EQ(m.get<Pin>().size(), 1u);
  EXPECT_EQ(m.get<Wall>().size(), 4u);  // one per movable particle
  // Auto rest length = initial distance; collision rest = sum of radii.
  EXPECT_EQ(m.get<Distance>()[0].rest, Real(1));
  EXPECT_NEAR(m.get<Collision>()[0].rest, Real(0.2), 4 * test::kEps);
}

TEST(Compile, DistanceIndexOutOfRange) {
  SceneDesc s = valid_scene();
  s.distances[1].a = 7;
  EXPECT_TRUE(scene_error_names(s, {"distances[1]", ".a", "7"}));
  s = valid_scene();
  s.distances[0].b = 4;  // one past the end
  EXPECT_TRUE(scene_error_names(s, {"distances[0]", ".b", "4"}));
  s = valid_scene();
  s.distances[1].b = -1;
  EXPECT_TRUE(scene_error_names(s, {"distances[1]", ".b", "-1"}));
}

TEST(Compile, CollisionIndexOutOfRange) {
  SceneDesc s = valid_scene();
  s.collisions[0].a = 12;
  EXPECT_TRUE(scene_error_names(s, {"collisions[0]", ".a", "12"}));
  s = valid_scene();
  s.collisions[0].b = -3;
  EXPECT_TRUE(scene_error_names(s, {"collisions[0]", ".b", "-3"}));
}

TEST(Compile, PinIndexOutOfRange) {
  SceneDesc s = valid_scene();
  s.pins.push_back(PinDesc{9, Vec3::Zero(), {}});
  EXPECT_TRUE(scene_error_names(s, {"pins[1]", ".particle", "9"}));
}

TEST(Compile, BadMass) {
  SceneDesc s = valid_scene();
  s.masses[2] = Real(-2.5);
  EXPECT_TRUE(scene_error_names(s, {"particles[2]", ".mass", "-2.5"}));
  s = valid_scene();
  s.masses[1] = kNaN;
  EXPECT_TRUE(scene_error_names(s, {"particles[1]", ".mass", "nan"}));
  s = valid_scene();
  s.masses[3] = kInf;
  EXPECT_TRUE(scene_error_names(s, {"particles[3]", ".mass", "inf"}));
}

TEST(Compile, NonFinitePositionAndVelocity) {
  SceneDesc s = valid_scene();
  s.positions[2].y() = kInf;
  EXPECT_TRUE(scene_error_names(s, {"particles[2]", ".position", "inf"}));
  s = valid_scene();
  s.positions[0].z() = kNaN;
  EXPECT_TRUE(scene_error_names(s, {"particles[0]", ".position", "nan"}));
  s = valid_scene();
  s.velocities.assign(4, Vec3::Zero());
  s.velocities[3].x() = -kInf;
  EXPECT_TRUE(scene_error_names(s, {"particles[3]", ".velocity", "-inf"}));
}

TEST(Compile, BadRadius) {
  SceneDesc s = valid_scene();
  s.radii[1] = Real(-0.25);
  EXPECT_TRUE(scene_error_names(s, {"particles[1]", ".radius", "-0.25"}));
}

TEST(Compile, ArraySizeMismatch) {
  SceneDesc s = valid_scene();
  s.masses.pop_back();
  EXPECT_TRUE(scene_error_names(s, {"masses", "3", "4"}));
  s = valid_scene();
  s.radii.push_back(0);
  EXPECT_TRUE(scene_error_names(s, {"radii", "5"}));
}

TEST(Compile, NegativeOrNonFiniteCompliance) {
  SceneDesc s = valid_scene();
  s.distances[1].mat.compliance = Real(-0.5);
  EXPECT_TRUE(scene_error_names(s, {"distances[1]", ".mat.compliance", "-0.5"}));
  s = valid_scene();
  s.collisions[0].mat.compliance = Real(-1e-3);
  EXPECT_TRUE(scene_error_names(s, {"collisions[0]", ".mat.compliance", "-0.001"}));
  s = valid_scene();
  s.pins[0].mat.compliance = kNaN;
  EXPECT_TRUE(scene_error_names(s, {"pins[0]", ".mat.compliance", "nan"}));
  s = valid_scene();
  s.planes[0].mat.compliance = kInf;
  EXPECT_TRUE(scene_error_names(s, {"planes[0]", ".mat.compliance", "inf"}));
}

TEST(Compile, BadDampingAndStiffness) {
  SceneDesc s = valid_scene();
  s.distances[0].mat.damping = Real(-3);
  EXPECT_TRUE(scene_error_names(s, {"distances[0]", ".mat.damping", "-3"}));
  s = valid_scene();
  s.distances[1].mat.stiffness = Real(1.5);
  EXPECT_TRUE(scene_error_names(s, {"distances[1]", ".mat.stiffness", "1.5"}));
  s = valid_scene();
  s.distances[1].mat.stiffness = kNaN;
  EXPECT_TRUE(scene_error_names(s, {"distances[1]", ".mat.stiffness", "nan"}));
}

TEST(Compile, DuplicateParticlesInOneConstraint) {
  SceneDesc s = valid_scene();
  s.distances[1].a = 2;  // b is 2 as well
  EXPECT_TRUE(scene_error_names(s, {"distances[1]", "duplicate", "2"}));
  s = valid_scene();
  s.collisions[0].b = 0;  // a is 0 as well
  EXPECT_TRUE(scene_error_names(s, {"collisions[0]", "duplicate", "0"}));
}

TEST(Compile, ZeroRestLength) {
  // Explicit rest 0, negative, NaN.
  SceneDesc s = valid_scene();
  s.distances[1].rest = Real(0);
  EXPECT_TRUE(scene_error_names(s, {"distances[1]", ".rest", "got 0"}));
  s.distances[1].rest = Real(-1);
  EXPECT_TRUE(scene_error_names(s, {"distances[1]", ".rest", "got -1"}));
  s.distances[1].rest = kNaN;
  EXPECT_TRUE(scene_error_names(s, {"distances[1]", ".rest", "nan"}));
  // Auto rest length with coincident particles: the message names both
  // particles and the resulting rest length 0.
  s = valid_scene();
  s.positions[3] = s.positions[2];
  s.distances.push_back(DistanceDesc{2, 3, std::nullopt, {}});
  EXPECT_TRUE(scene_error_names(s, {"distances[2]", ".rest", "particles 2 and 3", "would be 0"}));
}

TEST(Compile, CollisionWithBothRadiiZero) {
  SceneDesc s = valid_scene();
  s.radii[1] = 0;
  s.radii[2] = 0;
  s.collisions.push_back(CollisionDesc{1, 2, {}});
  EXPECT_TRUE(scene_error_names(s, {"collisions[1]", "particles 1 and 2", "radius 0"}));
  // One radius zero is fine: contact distance is the other radius.
  s.radii[2] = Real(0.1);
  EXPECT_NO_THROW(compile(s));
}

TEST(Compile, BadPlane) {
  SceneDesc s = valid_scene();
  s.planes.push_back(PlaneDesc{Vec3::Zero(), 0, {}});
  EXPECT_TRUE(scene_error_names(s, {"planes[1]", ".normal", "(0, 0, 0)"}));
  s = valid_scene();
  s.planes[0].normal = Vec3(0, kNaN, 0);
  EXPECT_TRUE(scene_error_names(s, {"planes[0]", ".normal", "nan"}));
  s = valid_scene();
  s.planes[0].offset = -kInf;
  EXPECT_TRUE(scene_error_names(s, {"planes[0]", ".offset", "-inf"}));
}

TEST(Compile, NonFinitePinTarget) {
  SceneDesc s = valid_scene();
  s.pins[0].target = Vec3(1, kInf, 0);
  EXPECT_TRUE(scene_error_names(s, {"pins[0]", ".target", "inf"}));
}

TEST(Compile, PlaneNormalIsNormalized) {
  SceneDesc s = valid_scene();
  s.planes[0] = PlaneDesc{Vec3(0, 0, Real(-4)), Real(2), {}};
  const Model m = compile(s);
  EXPECT_EQ(m.planes[0].normal, Vec3(0, 0, -1));
  EXPECT_EQ(m.planes[0].offset, Real(2));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
