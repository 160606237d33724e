// StepConfig::alternate_sweeps counts its sweeps across step() calls
// (State::sweeps): a host that steps one substep of one iteration at a time
// (the Bullet bridge with one XPBD substep per Bullet step) must get the same
// forward, backward, forward, ... sweeps as one step() with that many
// substeps. Before the count was kept in the state, every such call swept
// forward.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "support/xpbd_test.hpp"
#include "xpbd/builders.hpp"
#include "xpbd/compile.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

// A 12-particle rope pinned at one end, released horizontally: the sweep
// direction decides which end the corrections favour, so forward-only and
// alternating sweeps give different positions.
Model rope_model() {
  SceneDesc scene;
  RopeDesc r;
  r.n = 12;
  r.dir = Vec3::UnitX();
  r.spacing = Real(0.05);
  r.mass = Real(0.01);
  add_rope(scene, r);
  return compile(scene);
}

std::vector<Vec3> run(const Model& m, int calls, int substeps_per_call, Real h, bool alternate) {
  State s = make_state(m);
  StepConfig c;
  c.substeps = substeps_per_call;
  c.iterations = 1;
  c.dt = h * Real(substeps_per_call);  // substep h exactly (a power-of-two multiple)
  c.alternate_sweeps = alternate;
  for (int k = 0; k < calls; ++k) step(m, s, c);
  EXPECT_EQ(s.sweeps, std::uint64_t(calls * substeps_per_call));
  return s.x;
}

TEST(AlternateSweeps, ParityCarriesAcrossStepCalls) {
  const Model m = rope_model();
  const Real h = Real(1) / Real(256);  // s
  // 8 calls of one substep = one call of 8 substeps: the same operations in
  // the same order (static pin, same h), so the same bits.
  const auto one_at_a_time = run(m, 8, 1, h, true);
  const auto all_at_once = run(m, 1, 8, h, true);
  const auto two_by_four = run(m, 2, 4, h, true);
  ASSERT_EQ(one_at_a_time.size(), all_at_once.size());
  for (std::size_t i = 0; i < all_at_once.size(); ++i) {
    EXPECT_EQ(one_at_a_time[i], all_at_once[i]) << "particle " << i;
    EXPECT_EQ(two_by_four[i], all_at_once[i]) << "particle " << i;
  }
  // Control: forward-only sweeps end elsewhere (so the comparison above can
  // fail), by far more than round-off: 1e-5 m is over 100x the float
  // spacing of a 0.6 m coordinate (measured: 8.4e-5 m in double).
  const auto forward = run(m, 8, 1, h, false);
  Real diff = 0;
  for (std::size_t i = 0; i < forward.size(); ++i) diff = std::max(diff, (forward[i] - all_at_once[i]).norm());
  EXPECT_GT(diff, Real(1e-5));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
