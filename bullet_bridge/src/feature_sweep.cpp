// A rigid feature's path against a moving cloth triangle, with FCL's
// vertex-face continuous collision test (feature_sweep.hpp).
#include "feature_sweep.hpp"

#include <cmath>

#include <fcl/narrowphase/detail/traversal/collision/intersect.h>

namespace xpbd_bullet::detail {

namespace {
using P = fcl::Vector3<double>;
P point(const xpbd::Vec3& p) { return P(double(p.x()), double(p.y()), double(p.z())); }
}  // namespace

bool sweep_reaches_triangle(const xpbd::Vec3* path, int points, const std::array<xpbd::Vec3, 3>& a,
                            const std::array<xpbd::Vec3, 3>& b, xpbd::Real side, xpbd::Real start_distance,
                            xpbd::Real band) {
  if (points < 2) return false;
  // Inside the band at the start: the triangle itself (a crossing);
  // outside it: the triangle moved out to the band's edge on that side.
  const double offset = std::abs(double(start_distance)) <= double(band) ? 0.0 : double(side) * double(band);
  const int pieces = points - 1;
  auto corners = [&](double f, P out[3]) {
    for (int i = 0; i < 3; ++i) out[i] = point(a[i]) + f * (point(b[i]) - point(a[i]));
    const P n = (out[1] - out[0]).cross(out[2] - out[0]);
    const double len = n.norm();
    if (!(len > 0)) return false;
    for (int i = 0; i < 3; ++i) out[i] += (offset / len) * n;
    return true;
  };
  P t0[3], t1[3];
  if (!corners(0.0, t0)) return false;
  for (int k = 0; k < pieces; ++k) {
    if (!corners(double(k + 1) / pieces, t1)) return false;
    double when = 2;
    P at;
    if (fcl::detail::Intersect<double>::intersect_VF_filtered(t0[0], t0[1], t0[2], point(path[k]), t1[0], t1[1], t1[2],
                                                     point(path[k + 1]), &when, &at))
      return true;
    for (int i = 0; i < 3; ++i) t0[i] = t1[i];
  }
  return false;
}

}  // namespace xpbd_bullet::detail
