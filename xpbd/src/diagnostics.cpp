#include "xpbd/diagnostics.hpp"

#include <algorithm>
#include <cmath>

namespace xpbd {

Real kinetic_energy(const Model& m, const State& s) {
  Real e = 0;
  for (Index i = 0; i < m.num_particles(); ++i)
    if (m.inv_mass[i] > Real(0)) e += Real(0.5) * s.v[i].squaredNorm() / m.inv_mass[i];
  return e;
}

Real gravity_potential(const Model& m, const State& s, const Vec3& gravity) {
  Real e = 0;
  for (Index i = 0; i < m.num_particles(); ++i)
    if (m.inv_mass[i] > Real(0)) e -= gravity.dot(s.x[i]) / m.inv_mass[i];
  return e;
}

Vec3 linear_momentum(const Model& m, const State& s) {
  Vec3 p = Vec3::Zero();
  for (Index i = 0; i < m.num_particles(); ++i)
    if (m.inv_mass[i] > Real(0)) p += s.v[i] / m.inv_mass[i];
  return p;
}

Real total_mass(const Model& m) {
  Real t = 0;
  for (Real w : m.inv_mass)
    if (w > Real(0)) t += Real(1) / w;
  return t;
}

Strain distance_strain(const Model& m, const State& s) {
  Strain st;
  const auto& d = m.get<Distance>();
  if (d.empty()) return st;
  Real sum = 0;
  for (const auto& c : d) {
    const Real e = std::abs((s.x[c.p[0]] - s.x[c.p[1]]).norm() / c.rest - Real(1));
    st.max = std::max(st.max, e);
    sum += e;
  }
  st.mean = sum / static_cast<Real>(d.size());
  return st;
}

Real max_distance_strain(const Model& m, const State& s) {
  // Per element q = len^2 / rest^2, and the strain max(sqrt(max q) - 1,
  // 1 - sqrt(min q)). The bounds are tested by multiplication (a division
  // only where one moves), and a NaN q fails both tests, so it is skipped.
  const Vec3* const x = s.x.data();
  double hi = 1, lo = 1;  // strain 0
  const auto add = [&](const Vec3& xa, const Vec3& xb, Real rest) {
    const double dx = double(xa.x()) - double(xb.x()), dy = double(xa.y()) - double(xb.y()),
                 dz = double(xa.z()) - double(xb.z());
    const double l2 = dx * dx + dy * dy + dz * dz, r2 = double(rest) * double(rest);
    if (l2 > hi * r2) hi = l2 / r2;
    if (l2 < lo * r2) lo = l2 / r2;
  };
  const DistanceStream& ds = m.distance_stream;
  const auto& d = m.get<Distance>();
  if (ds.size() == d.size()) {  // compiled: 16 bytes per element to read instead of 40
    for (std::size_t j = 0; j < ds.size(); ++j) add(x[ds.a[j]], x[ds.b[j]], ds.rest[j]);
  } else {
    for (const Distance& c : d) add(x[c.p[0]], x[c.p[1]], c.rest);
  }
  return Real(std::max(std::sqrt(hi) - 1, 1 - std::sqrt(lo)));
}

Real max_distance_residual(const Model& m, const State& s) {
  const auto& d = m.get<Distance>();
  const auto& lambda = s.lambdas<Distance>();
  const double h = double(s.last_substep);
  const bool stepped = h > 0 && lambda.size() == d.size() && s.x_prev.size() == s.x.size();
  double worst = 0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    const Distance& c = d[k];
    const Vec3 dx = s.x[c.p[0]] - s.x[c.p[1]];
    const double len = double(dx.norm()), rest = double(c.rest);
    double r = len - rest;
    if (stepped && c.mat.compliance > Real(0)) {
      const double alpha = double(c.mat.compliance);
      r += alpha / (h * h) * double(lambda[k]);
      if (c.mat.damping > Real(0) && len > 0) {
        const Vec3 moved = (s.x[c.p[0]] - s.x_prev[c.p[0]]) - (s.x[c.p[1]] - s.x_prev[c.p[1]]);
        r += alpha * double(c.mat.damping) / h * double(dx.dot(moved)) / len;
      }
    }
    const double e = std::abs(r) / rest;
    if (e > worst) worst = e;  // a NaN fails the test and is skipped
  }
  return Real(worst);
}

}  // namespace xpbd
