// RunOptions::stage_times (scene_runner.hpp): an xpbd run of a built-in scene
// lists exactly the stages the scene uses (the hanging cloth pays nothing
// for contacts, the cloth on a sphere does), metrics.json carries them as
// stage_ms_per_frame, the trajectory is the same as without timing, and a
// btSoftBody run has no breakdown (and says why). No time value is asserted;
// only which stages are present.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "demos/builtin_scenes.hpp"
#include "demos/scene_runner.hpp"

namespace xpbd_demos {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

RunOptions options(const SceneSpec& spec, Solver solver, bool stages, int frames = 5) {
  RunOptions o = run_options(spec);
  o.solver = solver;
  o.frames = frames;
  o.stage_times = stages;
  return o;
}

// Timing changes no result: the same metrics, frame by frame, bit for bit.
void expect_same_series(const RunResult& a, const RunResult& b) {
  ASSERT_EQ(a.series.size(), b.series.size());
  for (std::size_t k = 0; k < a.series.size(); ++k) {
    EXPECT_EQ(a.series[k].kinetic_energy, b.series[k].kinetic_energy) << "frame " << k;
    EXPECT_EQ(a.series[k].potential_energy, b.series[k].potential_energy) << "frame " << k;
    EXPECT_EQ(a.series[k].max_strain, b.series[k].max_strain) << "frame " << k;
    EXPECT_EQ(a.series[k].max_penetration, b.series[k].max_penetration) << "frame " << k;
  }
}

std::set<std::string> stage_names(const RunResult& r) {
  std::set<std::string> out;
  for (const auto& [name, ms] : r.stage_ms_per_frame) out.insert(name);
  return out;
}

TEST(SceneStages, HangingClothHasNoContactStages) {
  const SceneSpec* spec = find_builtin_scene("hanging_cloth");
  ASSERT_NE(spec, nullptr);
  const RunResult timed = run_scene(*spec, options(*spec, Solver::xpbd, true));
  const RunResult plain = run_scene(*spec, options(*spec, Solver::xpbd, false));
  // Distance edges and two pins, no rigid bodies; "other" is Bullet's
  // (empty) rigid-body step and the glue around the stages.
  const std::set<std::string> expected = {"step_setup", "predict", "distance", "pin", "velocity_update", "other"};
  EXPECT_EQ(stage_names(timed), expected);
  EXPECT_TRUE(plain.stage_ms_per_frame.empty());
  const nlohmann::json j = to_json(timed);
  ASSERT_TRUE(j.contains("stage_ms_per_frame"));
  EXPECT_EQ(j["stage_ms_per_frame"].size(), expected.size());
  EXPECT_FALSE(to_json(plain).contains("stage_ms_per_frame"));
  expect_same_series(timed, plain);
}

TEST(SceneStages, ClothOnSphereHasContactStages) {
  const SceneSpec* spec = find_builtin_scene("cloth_on_sphere");
  ASSERT_NE(spec, nullptr);
  // 30 frames: the cloth reaches the sphere (body contacts) before the end.
  const RunResult r = run_scene(*spec, options(*spec, Solver::xpbd, true, 30));
  const RunResult plain = run_scene(*spec, options(*spec, Solver::xpbd, false, 30));
  const std::set<std::string> names = stage_names(r);
  for (const char* used : {"bridge_contacts", "body_contacts", "contact_velocities", "distance", "predict"})
    EXPECT_TRUE(names.count(used)) << used << " missing";
  for (const char* unused : {"self_collision_search", "self_collision_solve", "dihedral_bending", "pin"})
    EXPECT_FALSE(names.count(unused)) << unused << " present";
  expect_same_series(r, plain);
}

TEST(SceneStages, BulletRunHasNoBreakdown) {
  const SceneSpec* spec = find_builtin_scene("hanging_cloth");
  ASSERT_NE(spec, nullptr);
  const RunResult r = run_scene(*spec, options(*spec, Solver::bullet, true));
  EXPECT_TRUE(r.stage_ms_per_frame.empty());
  EXPECT_FALSE(to_json(r).contains("stage_ms_per_frame"));
  bool noted = false;
  for (const std::string& n : r.notes) noted = noted || n.find("stage_times") != std::string::npos;
  EXPECT_TRUE(noted);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd_demos
