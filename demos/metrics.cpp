#include "demos/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace xpbd_demos {

using xpbd::Real;

ClothMetrics measure(const xpbd::Model& model, std::span<const xpbd::Vec3> x,
                     std::span<const xpbd::Vec3> v) {
  if (x.size() != static_cast<std::size_t>(model.num_particles()) || v.size() != x.size())
    throw std::invalid_argument("measure: got " + std::to_string(x.size()) + " positions and " +
                                std::to_string(v.size()) + " velocities for " +
                                std::to_string(model.num_particles()) + " particles");
  ClothMetrics m;
  m.lowest_y = std::numeric_limits<Real>::infinity();
  for (std::size_t i = 0; i < x.size(); ++i) {
    m.finite = m.finite && x[i].allFinite() && v[i].allFinite();
    m.lowest_y = std::min(m.lowest_y, x[i].y());
    const Real w = model.inv_mass[i];
    if (w > Real(0)) m.kinetic_energy += Real(0.5) * v[i].squaredNorm() / w;
  }
  const auto& dist = model.get<xpbd::Distance>();
  Real sum = 0;
  for (const auto& d : dist) {
    const Real e = std::abs((x[static_cast<std::size_t>(d.p[0])] - x[static_cast<std::size_t>(d.p[1])]).norm() / d.rest - 1);
    sum += e;
    m.strain_max = std::max(m.strain_max, e);
  }
  if (!dist.empty()) m.strain_mean = sum / Real(dist.size());
  if (!m.finite) {
    const Real nan = std::numeric_limits<Real>::quiet_NaN();
    m.strain_mean = m.strain_max = m.lowest_y = m.kinetic_energy = nan;
  }
  return m;
}

}  // namespace xpbd_demos
