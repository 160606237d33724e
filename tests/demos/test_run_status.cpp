// The run's status (RunResult::status, metrics.json "status";
// xpbd/health.hpp): a strain past the scene's bound is over_stretched, a
// run that gains energy from the solver is exploded, one whose state is not
// finite is nonfinite, and energy a moving kinematic body gives is not
// counted as the solver's. References are closed forms written out here.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "demos/builtin_scenes.hpp"
#include "demos/scene_runner.hpp"
#include "xpbd/error.hpp"

namespace xpbd_demos {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;

constexpr Solver kAllSolvers[] = {Solver::xpbd, Solver::pbd, Solver::bullet};

// Three kinematic particles (mass 0) at x = 0, 1.1, 2.3 m with rest lengths
// 1 m: strains 0.1 and 0.2 in every frame, so the largest is 0.2 exactly.
SceneSpec stretched_chain(double max_strain) {
  SceneSpec s;
  s.name = "stretched";
  s.solver.max_strain = max_strain;
  auto& d = s.soft.particles;
  d.add_particle(Vec3(0, 0, 0), 0);
  d.add_particle(Vec3(Real(1.1), 0, 0), 0);
  d.add_particle(Vec3(Real(2.3), 0, 0), 0);
  d.distances.push_back(xpbd::DistanceDesc{0, 1, Real(1), {}});
  d.distances.push_back(xpbd::DistanceDesc{1, 2, Real(1), {}});
  s.solver.frames = 3;
  return s;
}

TEST(RunStatus, StrainPastTheScenesBoundIsOverStretched) {
  for (Solver solver : kAllSolvers) {
    SceneSpec spec = stretched_chain(0.25);
    RunOptions opt = run_options(spec);
    opt.solver = solver;
    EXPECT_EQ(run_scene(spec, opt).status, "ok") << solver_name(solver);
    spec = stretched_chain(0.15);
    opt = run_options(spec);
    opt.solver = solver;
    const RunResult r = run_scene(spec, opt);
    EXPECT_EQ(r.status, "over_stretched") << solver_name(solver);
    EXPECT_EQ(to_json(r).at("status"), "over_stretched");
    EXPECT_EQ(to_json(r).at("status_thresholds").at("max_strain"), r.options.health.max_strain);
  }
}

TEST(RunStatus, BadBoundNamesTheField) {
  SceneSpec spec = stretched_chain(0.25);
  RunOptions opt = run_options(spec);
  opt.health.max_strain = 0;
  try {
    run_scene(spec, opt);
    FAIL() << "a bound of 0 was accepted";
  } catch (const xpbd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("solver.max_strain"), std::string::npos) << e.what();
  }
}

// The built-in hanging cloth (pinned at two corners, released flat) at one
// substep of 1/60 s per frame diverges: within its 180 frames its kinetic
// energy passes ten times all the potential energy it has released. At its
// own budget (10 x 1) the same cloth swings within it: the energy ratio is
// below 1 (a damped pendulum cannot have more kinetic energy than it has
// released).
TEST(RunStatus, DivergingClothIsExplodedAndTheSameClothAtItsBudgetIsOk) {
  const SceneSpec* spec = find_builtin_scene("hanging_cloth");
  ASSERT_NE(spec, nullptr);
  RunOptions opt = run_options(*spec);
  const RunResult calm = run_scene(*spec, opt);
  EXPECT_EQ(calm.status, "ok");
  EXPECT_LT(calm.energy_ratio, 1.0);
  opt.substeps = 1;
  const RunResult r = run_scene(*spec, opt);
  EXPECT_EQ(r.status, "exploded") << "largest strain " << r.max_strain << ", energy ratio " << r.energy_ratio;
  EXPECT_GT(r.energy_ratio, opt.health.energy_factor);
}

TEST(RunStatus, NonFiniteRunIsNonfinite) {
  SceneSpec spec;
  spec.name = "blow_up";
  const Real v = std::numeric_limits<Real>::max() / 8;
  spec.soft.particles.add_particle(Vec3(0, 0, 0), 1, 0, Vec3(v, 0, 0));
  spec.soft.particles.add_particle(Vec3(1, 0, 0), 1, 0, Vec3(-v, 0, 0));
  spec.soft.particles.distances.push_back(xpbd::DistanceDesc{0, 1, std::nullopt, {}});
  RunOptions opt = run_options(spec);
  opt.frames = 5;
  const RunResult r = run_scene(spec, opt);
  EXPECT_FALSE(r.finite);
  EXPECT_EQ(r.status, "nonfinite");
}

// A particle of 1 kg at rest, no gravity, in the path of a kinematic box
// moving at 3 m/s: the box pushes it along, so it ends with about the box's
// speed: kinetic energy 1/2 m v^2 = 4.5 J, where the solver has released
// nothing (no gravity, no initial motion; the budget without the box would
// be the 1e-3 J floor). The box's energy input, 2 M v^2 (M = 1 kg: the most
// a wall moving at v can give a mass is 1/2 M (2v)^2), makes the budget
// 18 J + floor, so the ratio is 1/4 for a particle moving with the box and
// at most 1 for any elastic bounce.
TEST(RunStatus, EnergyFromAKinematicBodyIsNotTheSolvers) {
  for (Solver solver : {Solver::xpbd, Solver::pbd}) {
    SceneSpec spec;
    spec.name = "pushed";
    spec.solver.gravity = Vec3::Zero();
    spec.solver.frames = 30;
    spec.soft.particles.add_particle(Vec3(0, 0, 0), 1);
    RigidSpec box;
    box.shape.kind = ShapeKind::box;
    box.shape.half_extents = Vec3::Constant(Real(0.2));
    box.kinematic = true;
    box.position = Vec3(Real(-0.5), 0, 0);
    box.velocity = Vec3(3, 0, 0);
    spec.bodies.push_back(box);
    RunOptions opt = run_options(spec);
    opt.solver = solver;
    const RunResult r = run_scene(spec, opt);
    EXPECT_EQ(r.status, "ok") << solver_name(solver);
    EXPECT_GT(r.energy_ratio, 0.2) << solver_name(solver) << ": the box did not push the particle";
    EXPECT_LE(r.energy_ratio, 1.0) << solver_name(solver);
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd_demos
