#pragma once
// The generic constraint projection shared by every constraint type
// (Macklin et al. 2016, eqs. 18 and 26; seed report Algorithms 1 and 2).
#include <algorithm>
#include <span>

#include "xpbd/constraint_types.hpp"
#include "xpbd/step.hpp"

namespace xpbd {

// What one projection sweep needs besides the constraint array.
struct SolveContext {
  EvalContext eval;          // positions, pin targets, planes
  Vec3* x = nullptr;         // positions (written)
  const Vec3* x_prev = nullptr;  // positions at substep start (damping)
  const Real* inv_mass = nullptr;
  Real h = 0;                // s, substep
  Method method = Method::xpbd;
};

// Projects every element of `cs` once, in order (Gauss-Seidel).
//
// XPBD: dlambda = (-C - at*lambda - gamma*gradC.(x - x_prev)) / ((1 + gamma) * sum w|g|^2 + at)
//       with at = alpha/h^2 and gamma = alpha*beta/h.
// PBD:  dlambda = -k*C / sum w|g|^2   (proper inverse-mass weighting, not the
//       seed report's averaged mass factor).
// Inequalities clamp the accumulated lambda at >= 0, so a contact can only
// push, and can release within the iterations of one substep.
// An element whose gradient is undefined (eval() returns false) or whose
// denominator is not positive (all particles kinematic) is skipped.
template <class T, bool kDamped>
void project_all(std::span<const T> cs, std::span<Real> lambda, const SolveContext& sc) {
  constexpr int N = T::kArity;
  const Real inv_h = Real(1) / sc.h;
  const Real inv_h2 = inv_h * inv_h;
  const bool xpbd = sc.method == Method::xpbd;
  for (std::size_t k = 0; k < cs.size(); ++k) {
    const T& c = cs[k];
    Real C;
    Vec3 g[N];
    if (!T::eval(c, static_cast<Index>(k), sc.eval, C, g)) continue;
    if constexpr (T::kInequality) {
      if (C >= Real(0) && lambda[k] == Real(0)) continue;
    }
    Real w[N];
    Real wg = 0;
    for (int i = 0; i < N; ++i) {
      w[i] = sc.inv_mass[c.p[i]];
      wg += w[i] * g[i].squaredNorm();
    }
    Real dl;
    if (xpbd) {
      const Real at = c.mat.compliance * inv_h2;
      Real num = -C - at * lambda[k];
      Real den = wg + at;
      if constexpr (kDamped) {
        const Real gamma = c.mat.compliance * c.mat.damping * inv_h;
        Real gv = 0;
        for (int i = 0; i < N; ++i) gv += g[i].dot(sc.x[c.p[i]] - sc.x_prev[c.p[i]]);
        num -= gamma * gv;
        den += gamma * wg;
      }
      if (!(den > Real(0))) continue;
      dl = num / den;
    } else {
      if (!(wg > Real(0))) continue;
      dl = -c.mat.stiffness * C / wg;
    }
    if constexpr (T::kInequality) {
      const Real l = std::max(lambda[k] + dl, Real(0));
      dl = l - lambda[k];
      lambda[k] = l;
    } else {
      lambda[k] += dl;
    }
    for (int i = 0; i < N; ++i) sc.x[c.p[i]] += (w[i] * dl) * g[i];
  }
}

}  // namespace xpbd
