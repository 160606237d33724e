#pragma once
// Scalar and vector types shared by the whole solver.
//
// The scalar type is chosen at configure time (CMake option XPBD_DOUBLE, ON by
// default) and recorded in the generated header xpbd/config.hpp. The Bullet
// bridge links the Debian Bullet build of the same precision (bullet-float64
// for double, bullet for float).
#include <Eigen/Core>
#include <cstdint>
#include <limits>

#include "xpbd/config.hpp"

namespace xpbd {

#if XPBD_DOUBLE
using Real = double;
#else
using Real = float;
#endif

using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;
using Index = std::int32_t;

inline constexpr Real kEpsilon = std::numeric_limits<Real>::epsilon();

// Relative length below which a direction is treated as undefined (coincident
// points, zero-length edges). Kernels skip such constraints instead of dividing
// by a vanishing norm.
inline constexpr Real kDegenerateRel = Real(64) * kEpsilon;

}  // namespace xpbd
