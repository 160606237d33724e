// The joint solve of one particle's body contacts.
//
// Why: a light particle between two bodies (a cloth between a heavy box and
// the ground) is a mass-ratio problem for contact-by-contact Gauss-Seidel.
// The ground contact lifts the particle; the box contact then moves almost
// only the particle (inverse masses ~1000 : 0.5), back into the ground; the
// box is barely pushed and sinks through the cloth over the substeps.
// Solving the particle's contacts together makes it a rigid spacer: the
// ground holds it, and the box takes the whole correction.
//
// The problem. Contacts i = 1..k of particle p, each with
//   C_i = n_i.(x_p - p_i) - thickness_i >= 0,  compliance a_i = alpha_i/h^2,
// and multipliers lambda_i >= 0 accumulated over the substep. A change dl
// moves the particle by w_p sum_i dl_i n_i and body b_i by the positional
// impulse -dl_i n_i at lever arm r_i. To first order,
//   C_i' = C_i + sum_j (A_ij - a_i delta_ij) dl_j,
//   A_ij = w_p n_i.n_j + [b_i = b_j dynamic] (n_i.n_j / m + (r_i x n_i).I^-1 (r_j x n_j)) + a_i delta_ij.
// XPBD's condition C_i' + a_i lambda_i' = 0 for the contacts that push
// (lambda_i' > 0), and C_i' >= 0 with lambda_i' = 0 for the others: with
// rhs_i = -C_i - a_i lambda_i and resid = A dl - rhs,
//   resid_S = 0, lambda_S + dl_S >= 0;  dl_N = -lambda_N, resid_N >= 0
// for the active set S and the rest N. A is symmetric and positive
// semi-definite (positive definite when the particle has mass or the
// contacts are compliant), so the problem has one solution; with k <= 4 every
// active set is tried, largest first.
//
// Momentum: every dl_i acts equally and oppositely on the particle and on
// its body, as in the one-by-one solve.
#include "contact_block.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "rigid_internal.hpp"

namespace xpbd::rigid {

using namespace detail;

namespace {

using MatK = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxJointContacts, kMaxJointContacts>;
using VecK = Eigen::Matrix<Real, Eigen::Dynamic, 1, 0, kMaxJointContacts, 1>;

struct Row {
  std::size_t k = 0;  // contact index
  Frame f;            // at the current poses
  Vec3 rn = Vec3::Zero();  // (r x n) in the body frame, for the angular terms
  RigidBody* body = nullptr;
  bool dynamic = false;
};

}  // namespace

bool solve_contact_group(const Model& m, State& s, std::size_t head, Real inv_h2) {
  Row rows[kMaxJointContacts];
  int n = 0;
  for (Index j = Index(head); j >= 0; j = s.contact_next[static_cast<std::size_t>(j)]) {
    if (n == kMaxJointContacts) return false;
    Row& r = rows[n++];
    r.k = static_cast<std::size_t>(j);
    const BodyContact& c = s.contacts[r.k];
    r.body = &body_or_world(s, c.body);
    r.dynamic = c.body >= 0 && r.body->inv_mass > Real(0);
    r.f = contact_frame(*r.body, c, c.body < 0);
    r.rn = r.body->q.conjugate() * r.f.rw.cross(r.f.n);
  }
  const Index p = s.contacts[head].particle;
  const Real wp = m.inv_mass[p];

  MatK A(n, n);
  VecK rhs(n), lambda(n);
  bool any = false;
  Real scale = 0;
  for (int i = 0; i < n; ++i) {
    const BodyContact& c = s.contacts[rows[i].k];
    const Real C = rows[i].f.n.dot(s.x[p] - rows[i].f.p) - c.thickness;
    lambda(i) = s.contact_lambda[rows[i].k].normal;
    any = any || C < Real(0) || lambda(i) != Real(0);
    const Real at = c.compliance * inv_h2;
    rhs(i) = -C - at * lambda(i);
    for (int j = 0; j < n; ++j) {
      Real a = wp * rows[i].f.n.dot(rows[j].f.n);
      if (rows[i].dynamic && rows[i].body == rows[j].body)
        a += rows[i].body->inv_mass * rows[i].f.n.dot(rows[j].f.n) +
             rows[i].rn.dot(rows[i].body->inv_inertia.cwiseProduct(rows[j].rn));
      A(i, j) = a;
    }
    A(i, i) += at;
    scale = std::max({scale, std::abs(rhs(i)), std::abs(A(i, i) * lambda(i))});
  }
  if (!any) return true;  // nothing touches and nothing pushed: no change, as one by one
  if (!(scale < std::numeric_limits<Real>::infinity())) return false;

  // Every active set, largest first; the first that satisfies the conditions
  // is the solution.
  const Real eps = std::numeric_limits<Real>::epsilon();
  const Real tol = Real(64) * eps * (scale + Real(1e-30));
  VecK dl(n);
  for (unsigned mask = (1u << n) - 1;; --mask) {
    int act[kMaxJointContacts], na = 0;
    for (int i = 0; i < n; ++i) {
      if (mask & (1u << i)) {
        act[na++] = i;
        dl(i) = 0;
      } else {
        dl(i) = -lambda(i);
      }
    }
    bool ok = true;
    if (na > 0) {
      MatK As(na, na);
      VecK bs(na);
      for (int a = 0; a < na; ++a) {
        bs(a) = rhs(act[a]) - A.row(act[a]).dot(dl);
        for (int b = 0; b < na; ++b) As(a, b) = A(act[a], act[b]);
      }
      const Eigen::LDLT<MatK> ldlt(As);
      const auto d = ldlt.vectorD();
      const Real dmax = d.cwiseAbs().maxCoeff();
      ok = ldlt.info() == Eigen::Success && (d.array() > Real(64) * eps * dmax).all();
      if (ok) {
        const VecK x = ldlt.solve(bs);
        for (int a = 0; a < na; ++a) {
          dl(act[a]) = x(a);
          ok = ok && std::isfinite(x(a)) && lambda(act[a]) + x(a) >= -tol;
        }
      }
    }
    if (ok)
      for (int i = 0; i < n; ++i)
        if (!(mask & (1u << i))) ok = ok && A.row(i).dot(dl) - rhs(i) >= -tol;
    if (ok) break;
    if (mask == 0) return false;
  }

  // Apply: the particle once, each body by its contact's impulse.
  Vec3 dxp = Vec3::Zero();
  for (int i = 0; i < n; ++i) {
    ContactLambda& l = s.contact_lambda[rows[i].k];
    const Real ln = std::max(lambda(i) + dl(i), Real(0));
    const Real d = ln - l.normal;
    l.normal = ln;
    dxp += d * rows[i].f.n;
    apply_position_impulse(*rows[i].body, rows[i].f.rw, -d * rows[i].f.n);
    record_push(s, s.contacts[rows[i].k].body, -d * rows[i].f.n);
  }
  s.x[p] += wp * dxp;
  return true;
}

}  // namespace xpbd::rigid
