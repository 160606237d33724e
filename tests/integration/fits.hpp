#pragma once
// Fits of sampled trajectories for the integration tests that measure an
// acceleration or a period from a run. Kept out of support.hpp: the QR
// solve's templates cost every file that includes it about 8 s of compile
// time, and only two files use it.
#include <vector>

#include <Eigen/QR>

#include "support.hpp"

namespace xpbd_bullet::test {

// Least-squares fit of y(t) = c0 + c1 t + c2 t^2 / 2; returns {c0, c1, c2}
// (so c2 is the acceleration). Times are shifted by their mean for
// conditioning; the shift is undone in the result.
struct Quadratic {
  Real c0 = 0, v = 0, a = 0;  // value at t = 0, velocity at t = 0, acceleration
};
inline Quadratic fit_quadratic(const std::vector<Real>& t, const std::vector<Real>& y) {
  const std::size_t n = t.size();
  Real tm = 0;
  for (Real u : t) tm += u;
  tm /= Real(n);
  Eigen::Matrix<Real, Eigen::Dynamic, 3> A(n, 3);
  Eigen::Matrix<Real, Eigen::Dynamic, 1> b(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Real u = t[i] - tm;
    A(i, 0) = 1;
    A(i, 1) = u;
    A(i, 2) = Real(0.5) * u * u;
    b(i) = y[i];
  }
  const Eigen::Matrix<Real, 3, 1> c = A.colPivHouseholderQr().solve(b);
  // y = c0 + c1 u + c2 u^2/2 with u = t - tm.
  Quadratic q;
  q.a = c(2);
  q.v = c(1) - c(2) * tm;
  q.c0 = c(0) - c(1) * tm + Real(0.5) * c(2) * tm * tm;
  return q;
}

// Times (s) at which y(t) crosses `level` upwards, by linear interpolation
// between samples.
inline std::vector<Real> upward_crossings(const std::vector<Real>& t, const std::vector<Real>& y,
                                          Real level) {
  std::vector<Real> out;
  for (std::size_t i = 1; i < t.size(); ++i)
    if (y[i - 1] < level && y[i] >= level)
      out.push_back(t[i - 1] + (t[i] - t[i - 1]) * (level - y[i - 1]) / (y[i] - y[i - 1]));
  return out;
}

}  // namespace xpbd_bullet::test
