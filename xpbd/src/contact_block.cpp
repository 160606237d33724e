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
//
// Precision: the system is built and solved in double in every build.
// With the particle between two bodies, A's second pivot is
// w_p - w_p^2/(w_p + w_b), about w_b: a difference of numbers w_p/w_b
// times larger. In float (eps 1.2e-7) that cancellation lost the pivot,
// and the singularity test below rejected it, from a mass ratio of about
// 1e5 (a 0.4 kg 24 x 24 cloth under a 1000 kg box is 1.4e6): the box then
// sank through the cloth at any substep count. In double the same test
// holds to ratios of about 1e13. The positions stay in the build's scalar.
#include "contact_block.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "rigid_internal.hpp"

namespace xpbd::rigid {

using namespace detail;

namespace {

// The block's scalar (above: double in every build).
using D = double;
using MatK = Eigen::Matrix<D, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxJointContacts, kMaxJointContacts>;
using VecK = Eigen::Matrix<D, Eigen::Dynamic, 1, 0, kMaxJointContacts, 1>;
using Vec3D = Eigen::Matrix<D, 3, 1>;

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
    r.f = contact_frame(*r.body, c, c.body < 0, s.x[c.particle]);
    r.rn = r.body->q.conjugate() * r.f.rw.cross(r.f.n);
  }
  const Index p = s.contacts[head].particle;
  const D wp = m.inv_mass[p];

  MatK A(n, n);
  VecK rhs(n), lambda(n);
  bool any = false;
  D scale = 0;
  for (int i = 0; i < n; ++i) {
    const BodyContact& c = s.contacts[rows[i].k];
    const Real C = rows[i].f.n.dot(s.x[p] - rows[i].f.p) - c.thickness;
    lambda(i) = s.contact_lambda[rows[i].k].normal;
    any = any || C < Real(0) || lambda(i) != D(0);
    const D at = D(c.compliance) * D(inv_h2);
    rhs(i) = -D(C) - at * lambda(i);
    const Vec3D ni = rows[i].f.n.cast<D>();
    for (int j = 0; j < n; ++j) {
      const D nn = ni.dot(rows[j].f.n.cast<D>());
      D a = wp * nn;
      if (rows[i].dynamic && rows[i].body == rows[j].body)
        a += D(rows[i].body->inv_mass) * nn +
             rows[i].rn.cast<D>().dot(rows[i].body->inv_inertia.cast<D>().cwiseProduct(rows[j].rn.cast<D>()));
      A(i, j) = a;
    }
    A(i, i) += at;
    scale = std::max({scale, std::abs(rhs(i)), std::abs(A(i, i) * lambda(i))});
  }
  if (!any) return true;  // nothing touches and nothing pushed: no change, as one by one
  if (!(scale < std::numeric_limits<D>::infinity())) return false;

  // Every active set, largest first; the first that satisfies the conditions
  // is the solution.
  const D eps = std::numeric_limits<D>::epsilon();
  const D tol = D(64) * eps * (scale + D(1e-30));
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
      const D dmax = d.cwiseAbs().maxCoeff();
      ok = ldlt.info() == Eigen::Success && (d.array() > D(64) * eps * dmax).all();
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

  // Apply: the particle once (its move summed in double: for a spacer the
  // pushes nearly cancel), each body by its contact's impulse.
  Vec3D dxp = Vec3D::Zero();
  for (int i = 0; i < n; ++i) {
    ContactLambda& l = s.contact_lambda[rows[i].k];
    const D ln = std::max(lambda(i) + dl(i), D(0));
    const D dd = ln - D(l.normal);
    const Real d = Real(dd);
    l.normal = Real(ln);
    dxp += dd * rows[i].f.n.cast<D>();
    apply_position_impulse(*rows[i].body, rows[i].f.rw, -d * rows[i].f.n);
    record_push(s, s.contacts[rows[i].k].body, -d * rows[i].f.n);
  }
  s.x[p] += (wp * dxp).cast<Real>();
  return true;
}

}  // namespace xpbd::rigid
