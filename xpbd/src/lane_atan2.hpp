#pragma once
// atan2 for any lane type of stream_kernel.hpp (dihedral_kernel.hpp), in
// plain arithmetic and selects, so that the AVX2 lane computes 4 or 8 angles
// at once and every lane type gives the same bits.
//
// Reduction: with a = |x|, b = |y|, mx = max(a, b), mn = min(a, b),
//   atan(mn/mx) = t P(t^2),              t = mn/mx,            mn <= tan(pi/8) mx,
//               = pi/4 + t P(t^2),       t = (mn - mx)/(mn + mx), otherwise,
// so |t| <= tan(pi/8) and one division; then pi/2 - r where b > a, pi - r
// where x < 0, -r where y < 0. P interpolates atan(sqrt(s))/sqrt(s) at the
// Chebyshev nodes of [0, tan(pi/8)^2] (degree 11 in double, 5 in float;
// scripts/atan_coefficients.py computes the coefficients and prints the
// error of t P(t^2) evaluated in the target precision: 1.7e-16 relative in
// double, 9.0e-8 in float). The reduction adds a rounding or two of pi/2 and
// pi, so the angle is within a few units in the last place of atan2's.
// atan2(0, 0) is NaN here (0/0); the kernel never uses the angle of a
// degenerate hinge, where it happens.
#include <numbers>
#include <type_traits>

#include "xpbd/types.hpp"

namespace xpbd::detail {

template <class V>
[[gnu::always_inline]] inline V lane_atan2(V y, V x) {
  constexpr bool kDouble = std::is_same_v<Real, double>;
  constexpr Real pi = std::numbers::pi_v<Real>;
  const V zero(Real(0));
  const typename V::M x_neg = V::gt(zero, x), y_neg = V::gt(zero, y);
  const V a = V::select(x_neg, zero - x, x), b = V::select(y_neg, zero - y, y);
  const typename V::M swap = V::gt(b, a);
  const V mx = V::select(swap, b, a), mn = V::select(swap, a, b);
  // tan(pi/8) = sqrt(2) - 1
  const typename V::M big = V::gt(mn, V(Real(0.41421356237309503)) * mx);
  const V t = V::select(big, mn - mx, mn) / V::select(big, mn + mx, mx);
  const V s = t * t;
  V p;
  if constexpr (kDouble) {
    p = V(Real(-0.017805397205419446));
    p = p * s + V(Real(0.03796525745386594));
    p = p * s + V(Real(-0.05035102456601552));
    p = p * s + V(Real(0.05846878297330872));
    p = p * s + V(Real(-0.06662951813629191));
    p = p * s + V(Real(0.07692045330902225));
    p = p * s + V(Real(-0.09090896809064027));
    p = p * s + V(Real(0.11111110744919658));
    p = p * s + V(Real(-0.14285714279250245));
    p = p * s + V(Real(0.19999999999940893));
    p = p * s + V(Real(-0.3333333333333312));
    p = p * s + V(Real(1));
  } else {
    p = V(Real(-0.060263052582740784));
    p = p * s + V(Real(0.10569828748703003));
    p = p * s + V(Real(-0.14239533245563507));
    p = p * s + V(Real(0.19998182356357574));
    p = p * s + V(Real(-0.3333330750465393));
    p = p * s + V(Real(1));
  }
  V r = t * p;
  r = V::select(big, V(pi / 4) + r, r);
  r = V::select(swap, V(pi / 2) - r, r);
  r = V::select(x_neg, V(pi) - r, r);
  return V::select(y_neg, zero - r, r);
}

}  // namespace xpbd::detail
