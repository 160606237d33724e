// A coupled body that also rests on another Bullet body (docs/bridge-limitations.md,
// item 7): the built-in cloth_on_sphere scene, whose 0.2 kg box
// lies on the ground (centre at 0.1 m) and is pressed by the 0.3 kg cloth
// falling onto it. The box's contacts with the ground are solved inside the
// XPBD substeps (SystemSettings::coupled_static_contacts, on by default), and
// Bullet solves them once more per Bullet step, after XPBD.
//
// Asserted: the box ends at rest on the ground, its centre within 0.1 mm of
// 0.1 m, at 10, 20 and 100 substeps with one Bullet step per frame and at 10
// with Bullet stepped at every substep (before the ground contacts were
// solved inside the substeps it ended at 0.0876 m at 20 and 100; before the
// residual's clip knew the contacts' gaps it crept up and fell back, ending
// anywhere in 0.1000 .. 0.1012 m). Printed, not asserted: the lowest point
// of its path with one Bullet step per frame (the cloth's landing).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "demos/builtin_scenes.hpp"
#include "demos/scene_runner.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

struct Path {
  double lowest = 1e9, final = 0;
};

Path box_path(int substeps, int rigid_steps) {
  xpbd_demos::SceneSpec spec = *xpbd_demos::find_builtin_scene("cloth_on_sphere");
  spec.solver.frames = 120;
  std::size_t box = spec.bodies.size();
  for (std::size_t i = 0; i < spec.bodies.size(); ++i)
    if (spec.bodies[i].name == "box") box = i;
  EXPECT_LT(box, spec.bodies.size());
  xpbd_demos::RunOptions o = xpbd_demos::run_options(spec);
  o.substeps = substeps;
  o.iterations = 1;
  o.rigid_steps = rigid_steps;
  Path p;
  const auto r = xpbd_demos::run_scene(spec, o, [&](const xpbd_demos::FrameView& v) {
    if (box >= v.bodies.size()) return;
    const double y = double(v.bodies[box].position.y());
    p.lowest = std::min(p.lowest, y);
    p.final = y;
  });
  EXPECT_TRUE(r.finite);
  std::printf("box under cloth, %d substeps, %d Bullet steps per frame: centre at %.5f m after 2 s, lowest %.5f m "
              "(rest 0.1 m)\n",
              substeps, rigid_steps, p.final, p.lowest);
  return p;
}

TEST(BoxUnderCloth, RestsOnTheGroundAtTheDefaults) {
  EXPECT_NEAR(box_path(10, 1).final, 0.1, 1e-4);
  const Path every = box_path(10, 10);
  EXPECT_NEAR(every.final, 0.1, 1e-4);
  EXPECT_NEAR(every.lowest, 0.1, 1e-4);
  EXPECT_NEAR(box_path(20, 1).final, 0.1, 1e-4);
  EXPECT_NEAR(box_path(100, 1).final, 0.1, 1e-4);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
