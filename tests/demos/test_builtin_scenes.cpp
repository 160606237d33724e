// The built-in scenes (demos/builtin_scenes.cpp): each one round-trips
// through the scene file format to the same model, and runs with XPBD, PBD
// and (where it can express the scene) btSoftBody with a finite state.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "demos/builtin_scenes.hpp"
#include "demos/scene_file.hpp"
#include "demos/scene_runner.hpp"
#include "support/scene_compare.hpp"
#include "xpbd/xpbd.hpp"

namespace xpbd_demos {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

TEST(BuiltinScenes, AtLeastTenWithUniqueNamesAndDescriptions) {
  std::set<std::string> names;
  for (const SceneSpec& s : builtin_scenes()) {
    EXPECT_TRUE(names.insert(s.name).second) << "duplicate " << s.name;
    EXPECT_FALSE(s.description.empty()) << s.name;
    EXPECT_EQ(s.description.find('\n'), std::string::npos) << s.name;
  }
  EXPECT_GE(names.size(), 10u);
  EXPECT_NE(find_builtin_scene(kDefaultScene), nullptr);
}

// --dump, then load: the text xpbd-demo prints (scene_text of to_json) is
// parsed like a scene file and gives back the same scene: the expanded
// particle systems compile to the same model, element for element and bit for
// bit; bodies, attachments and settings compare equal field by field
// (support/scene_compare.hpp).
TEST(BuiltinScenes, EveryDumpLoadsBackToTheSameModel) {
  for (const SceneSpec& s : builtin_scenes()) {
    SCOPED_TRACE(s.name);
    test::round_trip(s);
  }
}

// Ten frames of every scene with every solver that can express it: the run
// completes with a finite state and writes metrics that say so. (The full
// runs at default settings are in scripts/scenes.sh and docs/scenes.md.)
TEST(BuiltinScenes, EveryOneRunsWithEverySolverThatCanExpressIt) {
  int bullet_runs = 0;
  for (const SceneSpec& s : builtin_scenes()) {
    for (Solver solver : {Solver::xpbd, Solver::pbd, Solver::bullet}) {
      SCOPED_TRACE(s.name + " / " + solver_name(solver));
      if (solver == Solver::bullet && !bullet_can_express(s)) continue;
      RunOptions opt = run_options(s);
      opt.solver = solver;
      opt.frames = 10;
      const RunResult r = run_scene(s, opt);
      EXPECT_TRUE(r.finite);
      EXPECT_EQ(r.frames_completed, 10);
      const nlohmann::json m = to_json(r);
      EXPECT_EQ(m.at("finite"), true);
      EXPECT_EQ(m.at("scene"), s.name);
      bullet_runs += solver == Solver::bullet;
    }
  }
  EXPECT_GE(bullet_runs, 5);  // most scenes are expressible (7 of the 11 when this was written)
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd_demos
