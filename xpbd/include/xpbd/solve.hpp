#pragma once
// The constraint projection shared by every constraint type
// (Macklin et al. 2016, eqs. 18 and 26; seed report Algorithms 1 and 2).
//
// project_all<T, damped>() is the entry point step() uses. It runs one of
//   - project_all_generic(): any type following the eval() convention of
//     constraints.hpp (arity 1..4, equality or inequality);
//   - project_dihedral() (solve_dihedral.hpp): the same update written out
//     for DihedralBending;
//   - the pair-distance kernel: the same update written out for the types
//     whose C is a signed distance between two particles (Distance,
//     Collision, Tether; see PairDistance below). They are most of a cloth's
//     elements. Knowing the gradient is +-(x_a - x_b)/|x_a - x_b| lets the
//     part that does not depend on positions (masses, compliance, the
//     division by the denominator) be done before the positions are read,
//     which shortens the chain of dependent operations from one projection
//     to the next (Gauss-Seidel: a projection reads what the previous ones
//     wrote). See docs/bench-distance.md for the measured effect.
// Both compute the same update, to round-off, in the same (array) order;
// tests/unit/test_solve_pair_distance.cpp checks that.
//
// project_all_coloured() (StepConfig::coloured) runs the pair-distance kernel
// over the elements in the order of a ColourSchedule (model.hpp) instead:
// colour by colour, no two elements of a colour sharing a particle
// (tests/unit/test_coloured_sweep.cpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

#include <type_traits>

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
  // Visit the elements of each type last to first (StepConfig::alternate_sweeps).
  bool reverse = false;
};

namespace detail {
// Element k of the j-th visit, in the direction sc.reverse selects.
inline std::size_t visit_index(std::size_t j, std::size_t n, bool reverse) {
  return reverse ? n - 1 - j : j;
}
}  // namespace detail

// Pair-distance constraint types: C = sign * (|x_a - x_b| - rest(c)) with
// gradients g_a = sign * n, g_b = -sign * n, n = (x_a - x_b)/|x_a - x_b|,
// skipped when |x_a - x_b| <= kDegenerateRel * rest(c) -- exactly what their
// eval() computes. A type listed here takes the pair-distance kernel; any
// other type takes the generic one.
template <class T>
struct PairDistance {
  static constexpr bool value = false;
};
template <>
struct PairDistance<Distance> {
  static constexpr bool value = true;
  static constexpr Real sign = 1;
  static Real rest(const Distance& c) { return c.rest; }
};
template <>
struct PairDistance<Collision> {
  static constexpr bool value = true;
  static constexpr Real sign = 1;
  static Real rest(const Collision& c) { return c.rest; }
};
template <>
struct PairDistance<Tether> {  // C = length - |x_a - x_b|
  static constexpr bool value = true;
  static constexpr Real sign = -1;
  static Real rest(const Tether& c) { return c.length; }
};

namespace detail {

// The generic projection of elements [0, n), in order (Gauss-Seidel).
//
// XPBD: dlambda = (-C - at*lambda - gamma*gradC.(x - x_prev)) / ((1 + gamma) * sum w|g|^2 + at)
//       with at = alpha/h^2 and gamma = alpha*beta/h.
// PBD:  dlambda = -k*C / sum w|g|^2   (proper inverse-mass weighting, not the
//       seed report's averaged mass factor).
// Inequalities clamp the accumulated lambda at >= 0, so a contact can only
// push, and can release within the iterations of one substep.
// An element whose gradient is undefined (eval() returns false) or whose
// denominator is not positive (all particles kinematic) is skipped.
template <class T, bool kDamped, bool kXpbd>
void project_generic(const T* cs, std::size_t n, Real* lambda, const SolveContext& sc) {
  constexpr int N = T::kArity;
  const Real inv_h = Real(1) / sc.h;
  const Real inv_h2 = inv_h * inv_h;
  // Local copies: the compiler cannot prove that writes to x leave sc alone.
  Vec3* const x = sc.x;
  const Vec3* const x_prev = sc.x_prev;
  const Real* const inv_mass = sc.inv_mass;
  const EvalContext ectx = sc.eval;
  const bool reverse = sc.reverse;
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t k = visit_index(j, n, reverse);
    const T& c = cs[k];
    Real C;
    Vec3 g[N];
    if (!T::eval(c, static_cast<Index>(k), ectx, C, g)) continue;
    if constexpr (T::kInequality) {
      if (C >= Real(0) && lambda[k] == Real(0)) continue;
    }
    Real w[N];
    Real wg = 0;
    for (int i = 0; i < N; ++i) {
      w[i] = inv_mass[c.p[i]];
      wg += w[i] * g[i].squaredNorm();
    }
    Real dl;
    if constexpr (kXpbd) {
      const Real at = c.mat.compliance * inv_h2;
      Real num = -C - at * lambda[k];
      Real den = wg + at;
      if constexpr (kDamped) {
        const Real gamma = c.mat.compliance * c.mat.damping * inv_h;
        Real gv = 0;
        for (int i = 0; i < N; ++i) gv += g[i].dot(x[c.p[i]] - x_prev[c.p[i]]);
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
    for (int i = 0; i < N; ++i) x[c.p[i]] += (w[i] * dl) * g[i];
  }
}

// The same update for a pair-distance type. With s = sign, d = x_a - x_b,
// L = |d|, g_a = s d/L = -g_b and sum w|g|^2 = w_a + w_b:
//   den     = (w_a + w_b) + at + gamma (w_a + w_b)    (PBD: w_a + w_b),
//   num     = (s rest - at lambda) - s L - gamma (s/L) d.(dx_a - dx_b)
//             (PBD: -k s (L - rest)),
//   dlambda = num * (1/den),
//   x_a += (dlambda w_a s/L) d,   x_b -= (dlambda w_b s/L) d.
// Compared with project_generic, 1/den and s rest - at lambda are formed
// before the positions are read, 1/L as L * (1/L^2) (the division runs beside
// the square root instead of after it), |g|^2 as 1, and w_a s/L beside num:
// the operations left between reading the positions and writing them back
// are the ones the next projection must wait for. Each rewrite changes the
// result by round-off only.
//
// kMapped (the coloured sweep): element k's multiplier is
// lambda[lambda_of[k]] instead of lambda[k] (cs is a permuted copy of the
// elements, lambda stays indexed by the original element).
template <class T, bool kDamped, bool kXpbd, bool kMapped = false>
void project_pair_distance(const T* cs, std::size_t n, Real* lambda, const SolveContext& sc,
                           const Index* lambda_of = nullptr) {
  using P = PairDistance<T>;
  constexpr Real sign = P::sign;
  const Real inv_h = Real(1) / sc.h;
  const Real inv_h2 = inv_h * inv_h;
  Vec3* const x = sc.x;
  const Vec3* const x_prev = sc.x_prev;
  const Real* const inv_mass = sc.inv_mass;
  const bool reverse = sc.reverse;
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t k = visit_index(j, n, reverse);
    const T& c = cs[k];
    Real& lam = lambda[kMapped ? static_cast<std::size_t>(lambda_of[k]) : k];
    const Index a = c.p[0], b = c.p[1];
    const Real rest = P::rest(c);

    // Independent of the positions.
    const Real wa = inv_mass[a], wb = inv_mass[b];
    const Real wg = wa + wb;
    Real at = 0, gamma = 0, den = wg;
    if constexpr (kXpbd) {
      at = c.mat.compliance * inv_h2;
      den += at;
      if constexpr (kDamped) {
        gamma = c.mat.compliance * c.mat.damping * inv_h;
        den += gamma * wg;
      }
    }
    if (!(den > Real(0))) continue;
    const Real inv_den = Real(1) / den;
    const Real num0 = sign * rest - at * lam;  // num = num0 - s L (XPBD)

    // Dependent on the positions.
    // The sums written out in the stream kernels' order (stream_kernel.hpp),
    // not as Eigen's squaredNorm and dot: those sum a 3-vector in an order
    // that depends on the build's vector width (x + (y + z) in float with
    // SSE, (x + y) + z in double), and the array order over its levels
    // (StepConfig::levels) must give this kernel's bits.
    const Vec3 d = x[a] - x[b];
    const Real q = (d.x() * d.x() + d.y() * d.y()) + d.z() * d.z();
    const Real len = std::sqrt(q);
    if (!(len > kDegenerateRel * rest)) continue;
    if constexpr (T::kInequality) {
      if (sign * (len - rest) >= Real(0) && lam == Real(0)) continue;
    }
    // 1/q overflows if q is subnormal, i.e. for lengths below ~1e-154 m
    // (double; ~1e-19 m in float), far below any physical scale: there 1/len
    // is used instead.
    const Real inv_len =
        q >= std::numeric_limits<Real>::min() ? len * (Real(1) / q) : Real(1) / len;
    const Real f = sign * inv_len;  // g_a = f d

    Real num;
    if constexpr (kXpbd) {
      num = num0 - sign * len;
      if constexpr (kDamped) {
        const Vec3 v = (x[a] - x_prev[a]) - (x[b] - x_prev[b]);
        num -= gamma * f * ((d.x() * v.x() + d.y() * v.y()) + d.z() * v.z());
      }
    } else {
      num = -c.mat.stiffness * (sign * (len - rest));
    }
    Real dl = num * inv_den;
    if constexpr (T::kInequality) {
      const Real l = std::max(lam + dl, Real(0));
      dl = l - lam;
      lam = l;
    } else {
      lam += dl;
    }
    x[a] += (dl * (wa * f)) * d;
    x[b] -= (dl * (wb * f)) * d;
  }
}

template <bool kDamped, bool kXpbd>
void project_dihedral(const DihedralBending* cs, std::size_t n, Real* lambda, const SolveContext& sc);

template <class T, bool kDamped, bool kXpbd>
void project(const T* cs, std::size_t n, Real* lambda, const SolveContext& sc) {
  if constexpr (PairDistance<T>::value)
    project_pair_distance<T, kDamped, kXpbd>(cs, n, lambda, sc);
  else if constexpr (std::is_same_v<T, DihedralBending>)
    project_dihedral<kDamped, kXpbd>(cs, n, lambda, sc);
  else
    project_generic<T, kDamped, kXpbd>(cs, n, lambda, sc);
}

}  // namespace detail

// Projects every element of `cs` once, in order (Gauss-Seidel; last to first
// if sc.reverse), with the
// pair-distance kernel where it applies and the generic one otherwise.
// `lambda` is parallel to `cs`. kDamped selects the variant that reads
// x_prev for constraint damping (XPBD only; PBD has no damping).
template <class T, bool kDamped>
void project_all(std::span<const T> cs, std::span<Real> lambda, const SolveContext& sc) {
  if (sc.method == Method::xpbd)
    detail::project<T, kDamped, true>(cs.data(), cs.size(), lambda.data(), sc);
  else
    detail::project<T, false, false>(cs.data(), cs.size(), lambda.data(), sc);
}

// Projects every element once in a colour order (StepConfig::coloured):
// `by_colour` holds the elements of a pair-distance type in the order of
// their ColourSchedule (model.hpp), by_colour[j] being element order[j];
// `lambda` stays indexed by element (lambda[order[j]] belongs to
// by_colour[j]). Runs the pair-distance kernel over by_colour, so the result
// equals project_all over the elements laid out in schedule order. Within a
// colour consecutive projections share no particle, so none waits for the
// previous one's store (docs/bench-coloured.md, "Coloured sweep"). A reversed
// sweep (sc.reverse) runs by_colour last to first: the colours last to first
// (the order within a colour does not change the result).
template <class T, bool kDamped>
void project_all_coloured(std::span<const T> by_colour, std::span<const Index> order,
                          std::span<Real> lambda, const SolveContext& sc) {
  static_assert(PairDistance<T>::value, "pair-distance types only");
  if (sc.method == Method::xpbd)
    detail::project_pair_distance<T, kDamped, true, true>(by_colour.data(), by_colour.size(),
                                                          lambda.data(), sc, order.data());
  else
    detail::project_pair_distance<T, false, false, true>(by_colour.data(), by_colour.size(),
                                                         lambda.data(), sc, order.data());
}

// The generic projection for any type, also for pair-distance types (tests
// and benchmarks compare the two kernels with it).
template <class T, bool kDamped>
void project_all_generic(std::span<const T> cs, std::span<Real> lambda, const SolveContext& sc) {
  if (sc.method == Method::xpbd)
    detail::project_generic<T, kDamped, true>(cs.data(), cs.size(), lambda.data(), sc);
  else
    detail::project_generic<T, false, false>(cs.data(), cs.size(), lambda.data(), sc);
}

}  // namespace xpbd

#include "xpbd/solve_dihedral.hpp"  // DihedralBending's kernel (needs the above)
