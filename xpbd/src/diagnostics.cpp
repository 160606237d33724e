#include "xpbd/diagnostics.hpp"

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

}  // namespace xpbd
