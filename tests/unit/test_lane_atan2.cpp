// lane_atan2 (xpbd/src/lane_atan2.hpp), the polynomial atan2 of the
// dihedral stream kernel, against std::atan2 on the scalar lane: every
// quadrant, both axes, angles near the reduction's seams (pi/8, pi/4, 3pi/8
// and their mirrors), lengths from 1e-6 to 1e6. The error bound: the
// polynomial's own 1.7e-16 relative (double; 9.0e-8 in float) plus a
// rounding each of pi/4, pi/2 and pi, so a few units in the last place of
// pi: 8 eps absolute.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "../../xpbd/src/lane_atan2.hpp"
#include "../../xpbd/src/stream_kernel.hpp"
#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;
using detail::ScalarLane;

Real lane(Real y, Real x) { return detail::lane_atan2(ScalarLane(y), ScalarLane(x)).v; }

TEST(LaneAtan2, MatchesStdAtan2InEveryQuadrant) {
  constexpr Real pi = std::numbers::pi_v<Real>;
  Real worst = 0;
  int n = 0;
  for (Real r : {Real(1e-6), Real(0.37), Real(1), Real(2.5e3), Real(1e6)}) {
    for (int k = -20000; k <= 20000; ++k) {
      const Real th = pi * Real(k) / Real(20000);
      const Real y = r * std::sin(th), x = r * std::cos(th);
      worst = std::max(worst, std::abs(lane(y, x) - std::atan2(y, x)));
      ++n;
    }
    for (int q = 1; q < 16; q += 2)  // the seams, and a hair off either side
      for (Real off : {Real(-1e-7), Real(0), Real(1e-7)}) {
        const Real th = pi * Real(q) / 8 + off - pi;
        const Real y = r * std::sin(th), x = r * std::cos(th);
        worst = std::max(worst, std::abs(lane(y, x) - std::atan2(y, x)));
      }
  }
  std::printf("lane_atan2: largest error %.3g rad over %d angles (eps %.3g)\n", double(worst), n, double(kEps));
  EXPECT_LE(worst, 8 * kEps);
}

TEST(LaneAtan2, AxesAndSignsAreExact) {
  constexpr Real pi = std::numbers::pi_v<Real>;
  EXPECT_EQ(lane(0, 1), Real(0));
  EXPECT_EQ(lane(0, -1), pi);
  EXPECT_EQ(lane(1, 0), pi / 2);
  EXPECT_EQ(lane(-1, 0), -pi / 2);
  EXPECT_NEAR(lane(1, 1), pi / 4, kEps);
  EXPECT_NEAR(lane(-1, -1), -3 * pi / 4, 4 * kEps);
  // Odd in y: atan2(-y, x) = -atan2(y, x) exactly.
  for (Real y : {Real(0.1), Real(0.7), Real(3)})
    for (Real x : {Real(-2), Real(0.5), Real(4)}) EXPECT_EQ(lane(-y, x), -lane(y, x));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
