// The determinism hash (demos/state_hash.hpp, xpbd-demo --hash).
//
// ExpectedHashesOfBuiltInScenes is the one test that holds outputs the code
// produced: the final-state hashes of a few built-in scenes, per precision,
// recorded when this test was written. It fails whenever a change of the
// solver, the bridge, the compiler or Bullet changes any bit of those
// results, so that a change of results is always a decision: if the change
// is intended, put the printed hashes in kExpected, and say why in the
// commit (docs/reliability.md).
#include <gtest/gtest.h>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "demos/builtin_scenes.hpp"
#include "demos/scene_runner.hpp"
#include "demos/state_hash.hpp"

namespace xpbd_demos {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;

struct Case {
  const char* scene;
  Solver solver;
  std::uint64_t expected_double, expected_float;
};

// Recorded 2026-11-26 (gcc 12.2, Bullet 3.24, Debian 12, x86-64): 60 frames
// of each scene at its own budget. cloth_on_sphere with XPBD again on
// 2026-11-28: a particle contact's push and friction act at the body's
// point under the particle (xpbd/src/rigid_internal.hpp, contact_frame);
// and again later that day: the settle pass moves a dynamic body out of a
// particle it cannot put outside every body (ContactSettings::wedges).
// And on 2026-11-29: a particle contact with a primitive shape keeps the
// point and normal of the shape's frame, not their round trip through world
// coordinates (world_contacts.cpp, particle_contacts_of).
// And the float hashes of cloth_on_sphere (XPBD) and hanging_cloth (PBD)
// on 2026-11-29, later: the array-order pair-distance kernel sums a squared
// length as (x^2 + y^2) + z^2 (solve.hpp), where Eigen's squaredNorm summed
// x^2 + (y^2 + z^2) in float, so that the array order over its levels gives
// its bits. The double hashes did not change (Eigen's double sum was
// already in that order).
constexpr Case kExpected[] = {
    {"rope_pendulum", Solver::xpbd, 0x21dded8287a38c42, 0x65ebb9b1dd318006},
    {"cloth_on_sphere", Solver::xpbd, 0x680f7d99f81100b4, 0xe89c70db44b0d168},
    {"hanging_cloth", Solver::pbd, 0xf2e27dbbc7fc99f0, 0x818ec63df5b48201},
    {"cloth_on_sphere", Solver::bullet, 0xdfcdce1c1315d944, 0xc4a6aada6e873e7a},
};

std::uint64_t run_hash(const SceneSpec& spec, Solver solver, int frames, int threads = 1) {
  RunOptions opt = run_options(spec);
  opt.solver = solver;
  opt.frames = frames;
  opt.threads = threads;
  const RunResult r = run_scene(spec, opt);
  EXPECT_TRUE(r.finite) << spec.name;
  return r.state_hash;
}

TEST(StateHash, ExpectedHashesOfBuiltInScenes) {
  const bool dbl = sizeof(Real) == 8;
  std::string table;
  bool changed = false;
  for (const Case& c : kExpected) {
    const SceneSpec* spec = find_builtin_scene(c.scene);
    ASSERT_NE(spec, nullptr) << c.scene;
    const std::uint64_t h = run_hash(*spec, c.solver, 60);
    const std::uint64_t want = dbl ? c.expected_double : c.expected_float;
    char line[160];
    std::snprintf(line, sizeof line, "  %-16s %-7s %s: 0x%016" PRIx64 " (expected 0x%016" PRIx64 ")\n", c.scene,
                  solver_name(c.solver), dbl ? "double" : "float", h, want);
    table += line;
    changed = changed || h != want;
  }
  EXPECT_FALSE(changed) << "The final state of a built-in scene changed (60 frames, bit for bit):\n"
                        << table
                        << "If the change of results is intended, put the new hashes into kExpected in "
                           "tests/demos/test_state_hash.cpp and say why in the commit (docs/reliability.md).";
}

// The coloured sweep on 1, 2 and 3 threads: the same bits.
TEST(StateHash, SameAtEveryThreadCount) {
  SceneSpec spec = *find_builtin_scene("hanging_cloth");
  spec.solver.coloured = true;
  const std::uint64_t one = run_hash(spec, Solver::xpbd, 30, 1);
  EXPECT_EQ(run_hash(spec, Solver::xpbd, 30, 2), one);
  EXPECT_EQ(run_hash(spec, Solver::xpbd, 30, 3), one);
}

// The hash sees every bit of every value, and the order of the values.
TEST(StateHash, OneBitOfAnyValueChangesIt) {
  std::vector<Vec3> x = {Vec3(1, 2, 3), Vec3(-4, 5, 0)}, v = {Vec3(0, 0, 0), Vec3(Real(0.5), 0, 0)};
  std::vector<BodyPose> b(1);
  b[0].position = Vec3(0, 1, 0);
  const std::uint64_t h = state_hash(x, v, b);
  EXPECT_EQ(state_hash(x, v, b), h);
  auto differs = [&](auto change) {
    auto x2 = x;
    auto v2 = v;
    auto b2 = b;
    change(x2, v2, b2);
    return state_hash(x2, v2, b2) != h;
  };
  EXPECT_TRUE(differs([](auto& x2, auto&, auto&) { x2[1][2] = -Real(0); }));  // -0.0 against 0.0
  EXPECT_TRUE(differs([](auto& x2, auto&, auto&) { x2[0][0] = std::nextafter(Real(1), Real(2)); }));
  EXPECT_TRUE(differs([](auto&, auto& v2, auto&) { v2[0][1] = std::numeric_limits<Real>::denorm_min(); }));
  EXPECT_TRUE(differs([](auto&, auto&, auto& b2) { b2[0].orientation[3] = std::nextafter(Real(0), Real(1)); }));
  EXPECT_TRUE(differs([](auto& x2, auto&, auto&) { std::swap(x2[0], x2[1]); }));
  EXPECT_TRUE(differs([](auto& x2, auto& v2, auto&) { std::swap(x2, v2); }));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd_demos
