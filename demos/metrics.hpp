#pragma once
// Shape and energy measurements computed the same way for every method from
// plain arrays of positions and velocities, so XPBD, PBD and btSoftBody are
// judged by one piece of code.
#include <span>

#include "xpbd/model.hpp"
#include "xpbd/types.hpp"

namespace xpbd_demos {

struct ClothMetrics {
  xpbd::Real strain_mean = 0;     // dimensionless, mean over distance constraints of |len/rest - 1|
  xpbd::Real strain_max = 0;      // dimensionless, max of the same
  xpbd::Real lowest_y = 0;        // m, smallest y over all particles
  xpbd::Real kinetic_energy = 0;  // J, sum of m |v|^2 / 2 over movable particles
  bool finite = true;             // all positions and velocities finite
};

// x, v: one entry per particle of `model` (m, m/s). The rest lengths and
// masses come from `model`.
ClothMetrics measure(const xpbd::Model& model, std::span<const xpbd::Vec3> x,
                     std::span<const xpbd::Vec3> v);

}  // namespace xpbd_demos
