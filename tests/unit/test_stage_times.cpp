// StepConfig::times (profile.hpp): the per-stage breakdown lists exactly the
// stages a scene uses, each run counted once per step / substep / iteration,
// and timing does not change the trajectory by a single bit. No timing value
// is asserted (wall time is not a pass/fail criterion); the tests check which
// stages ran and how often, which follows from the step's structure.
#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <string>

#include "support/xpbd_test.hpp"
#include "xpbd/builders.hpp"
#include "xpbd/profile.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

constexpr int kSteps = 5, kSubsteps = 4, kIterations = 3;

StepConfig config(StageTimes* times) {
  StepConfig cfg;
  cfg.substeps = kSubsteps;
  cfg.iterations = kIterations;
  cfg.times = times;
  return cfg;
}

// 8x8 cloth pinned at its top corners: distance edges and pins only.
SceneDesc plain_cloth() {
  SceneDesc s;
  ClothGridDesc d;
  d.nx = d.ny = 8;
  d.pins = ClothPins::top_corners;
  add_cloth_grid(s, d);
  return s;
}

// The same cloth with dihedral bending and particle self-collision (contact
// distance 0.35 m > the 0.32 m between the closest unconnected particles,
// (i,j)-(i+1,j+2) at spacing 1/7 m, so pairs exist from the first step).
SceneDesc busy_cloth() {
  SceneDesc s;
  ClothGridDesc d;
  d.nx = d.ny = 8;
  d.pins = ClothPins::top_corners;
  d.set_bending(ClothBending::dihedral, Material{});
  add_cloth_grid(s, d);
  s.self_collision.enabled = true;
  s.self_collision.distance = Real(0.35);
  return s;
}

// Host-supplied rigid interactions with the static world (body -1): a ground
// contact under the bottom-left particle, a world attachment of the
// bottom-right one, and a static feature point against one triangle.
void add_rigid_work(const Model& m, State& st) {
  const Index bl = 7 * 8, br = 7 * 8 + 7;
  BodyContact c;
  c.particle = bl;
  c.r = Vec3(0, Real(-1.2), 0);
  c.n = Vec3::UnitY();
  c.dynamic_friction = Real(0.5);
  st.contacts.push_back(c);
  st.attachments.push_back(BodyAttachment{br, -1, m.x0[std::size_t(br)], 0});
  BodyTriangleContact t;
  t.r = Vec3(Real(0.5), Real(-0.5), Real(0.1));
  t.tri = {Index(3 * 8 + 3), Index(3 * 8 + 4), Index(4 * 8 + 4)};
  st.triangle_contacts.push_back(t);
}

std::set<std::string> present(const StageTimes& t) {
  std::set<std::string> out;
  for (std::size_t k = 0; k < stage::count; ++k)
    if (t.calls[k] > 0) out.insert(stage_name(k));
  return out;
}

// Runs kSteps steps twice, without and with timing; the trajectories must be
// identical bit for bit (timing only reads the clock around the same calls).
StageTimes run_both(const Model& m, bool rigid) {
  State a = make_state(m), b = make_state(m);
  if (rigid) {
    add_rigid_work(m, a);
    add_rigid_work(m, b);
  }
  StageTimes times;
  for (int k = 0; k < kSteps; ++k) {
    step(m, a, config(nullptr));
    step(m, b, config(&times));
  }
  const std::size_t bytes = a.x.size() * sizeof(Vec3);
  EXPECT_EQ(std::memcmp(a.x.data(), b.x.data(), bytes), 0) << "positions differ with timing on";
  EXPECT_EQ(std::memcmp(a.v.data(), b.v.data(), bytes), 0) << "velocities differ with timing on";
  EXPECT_EQ(times.steps, kSteps);
  // A stage that never ran has no time either.
  for (std::size_t k = 0; k < stage::count; ++k)
    if (times.calls[k] == 0) {
      EXPECT_EQ(times.ns[k], 0) << stage_name(k);
    }
  return times;
}

TEST(StageTimes, NamesAreUniqueAndCoverEveryStage) {
  std::set<std::string> names;
  for (std::size_t k = 0; k < stage::count; ++k) names.insert(stage_name(k));
  EXPECT_EQ(names.size(), stage::count);
  EXPECT_STREQ(stage_name(stage::of<Distance>), "distance");
  EXPECT_STREQ(stage_name(stage::of<DihedralBending>), "dihedral_bending");
  EXPECT_STREQ(stage_name(stage::of<Pin>), "pin");
  EXPECT_STREQ(stage_name(stage::count), "?");
}

TEST(StageTimes, PlainClothShowsOnlyItsStages) {
  const Model m = compile(plain_cloth());
  const StageTimes t = run_both(m, false);
  const std::set<std::string> expected = {"step_setup", "predict", "distance", "pin", "velocity_update"};
  EXPECT_EQ(present(t), expected);
  // Runs: once per step, per substep, per iteration.
  EXPECT_EQ(t.calls[stage::step_setup], kSteps);
  EXPECT_EQ(t.calls[stage::predict], kSteps * kSubsteps);
  EXPECT_EQ(t.calls[stage::velocity_update], kSteps * kSubsteps);
  EXPECT_EQ(t.calls[stage::of<Distance>], kSteps * kSubsteps * kIterations);
  EXPECT_EQ(t.calls[stage::of<Pin>], kSteps * kSubsteps * kIterations);
}

TEST(StageTimes, BusyClothShowsBendingSelfCollisionAndContacts) {
  const Model m = compile(busy_cloth());
  const StageTimes t = run_both(m, true);
  const std::set<std::string> expected = {
      "step_setup",           "self_collision_search", "predict",           "distance",
      "dihedral_bending",     "pin",                   "self_collision_solve", "body_attachments",
      "body_contacts",        "triangle_contacts",     "velocity_update",   "contact_velocities"};
  EXPECT_EQ(present(t), expected);
  EXPECT_EQ(t.calls[stage::self_collision_search], kSteps);
  EXPECT_EQ(t.calls[stage::of<DihedralBending>], kSteps * kSubsteps * kIterations);
  EXPECT_EQ(t.calls[stage::body_contacts], kSteps * kSubsteps * kIterations);
  EXPECT_EQ(t.calls[stage::contact_velocities], kSteps * kSubsteps);
}

TEST(StageTimes, AccumulatesAcrossRunsAndClears) {
  const Model m = compile(plain_cloth());
  State s = make_state(m);
  StageTimes t;
  step(m, s, config(&t));
  StageTimes sum = t;
  sum += t;
  EXPECT_EQ(sum.steps, 2);
  EXPECT_EQ(sum.calls[stage::predict], 2 * kSubsteps);
  sum.clear();
  EXPECT_EQ(sum.steps, 0);
  EXPECT_EQ(sum.calls[stage::predict], 0);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
