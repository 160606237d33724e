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
// The friction's system: two tangent directions per contact.
using MatT = Eigen::Matrix<D, Eigen::Dynamic, Eigen::Dynamic, 0, 2 * kMaxJointContacts, 2 * kMaxJointContacts>;
using VecT = Eigen::Matrix<D, Eigen::Dynamic, 1, 0, 2 * kMaxJointContacts, 1>;

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

// The friction of one particle's contacts, jointly.
//
// Why: the same mass ratio as the normal parts. A box sliding on a cloth
// that lies on the ground: one by one, the box's friction brings the
// particle up to the box's speed (it moves the particle, not the box, with
// inverse masses ~1000 : 0.001), and the ground's then stops the particle
// again. The box loses only the momentum of the particles under it in each
// substep: a 1000 kg box pushed at 1 m/s slowed by 0.025 m/s^2 where
// Coulomb gives mu g = 4.9 m/s^2, and slid 1.56 m where it stops in
// 0.10 m (docs/squeeze.md).
//
// The problem. For each contact i that pushes (lambda_n,i > 0) and has
// friction, g_i = T_i^T ((x_p - x_p,start) - (p_i - p_i,start)) is the
// particle's slip over the substep against the body's material point under
// it, in the contact's tangent plane (basis T_i, 3 x 2). A tangential
// positional impulse T_j u_j moves the particle by w_p T_j u_j and body b_j
// by -T_j u_j at lever arm r_j, so to first order
//   g_i' = g_i + sum_j K_ij u_j,
//   K_ij = T_i^T (w_p I + [b_i = b_j dynamic] W_b(r_i, r_j)) T_j,
// W_b(r_i, r_j) = I/m + [r_i]x^T I^-1 [r_j]x. Static friction is g' = 0, with
// |u_i| inside the cone mu_s,i lambda_n,i (the accumulated multiplier
// included). A contact whose u_i leaves its cone slides: its impulse is
// clamped to mu_d,i lambda_n,i in the same direction and held, and the
// others are solved again with it (at most one contact per round). K is
// symmetric positive semi-definite (singular for a particle in a static
// corner, whose tangent planes overlap); Eigen's LDLT gives a solution
// there. The box on the cloth then gets mu_d lambda_n from the particle and
// the ground holds the particle: Coulomb's law between the two bodies.
//
// The velocity pass leaves these contacts' dynamic friction alone
// (ContactLambda::joint): it was applied here, at the position level.
bool solve_friction_group(const Model& m, State& s, std::size_t head) {
  struct TRow {
    std::size_t k = 0;
    Frame f;
    Vec3D t[2];   // tangent basis (world)
    Vec3D rt[2];  // (r x t) in the body frame
    RigidBody* body = nullptr;
    bool dynamic = false;
  };
  TRow rows[kMaxJointContacts];
  int n = 0;
  const Index p = s.contacts[head].particle;
  for (Index j = Index(head); j >= 0; j = s.contact_next[static_cast<std::size_t>(j)]) {
    const std::size_t k = static_cast<std::size_t>(j);
    const BodyContact& c = s.contacts[k];
    if (s.contact_lambda[k].normal <= Real(0)) continue;
    if (c.static_friction <= Real(0) && c.dynamic_friction <= Real(0)) continue;
    if (n == kMaxJointContacts) return false;
    TRow& r = rows[n++];
    r.k = k;
    r.body = &body_or_world(s, c.body);
    r.dynamic = c.body >= 0 && r.body->inv_mass > Real(0);
    r.f = contact_frame(*r.body, c, c.body < 0, s.x[p]);
    const Vec3D nd = r.f.n.cast<D>();
    r.t[0] = nd.unitOrthogonal();
    r.t[1] = nd.cross(r.t[0]);
    for (int a = 0; a < 2; ++a)
      r.rt[a] = (r.body->q.conjugate() * r.f.rw.cross(r.t[a].cast<Real>())).cast<D>();
  }
  if (n < 2) return false;  // one by one: the same as the particle's lone contact
  const D wp = m.inv_mass[p];

  const int n2 = 2 * n;
  MatT K(n2, n2);
  VecT g(n2), u(n2);
  VecK cone_s(n), cone_d(n), acc(n);
  for (int i = 0; i < n; ++i) {
    const BodyContact& c = s.contacts[rows[i].k];
    const ContactLambda& l = s.contact_lambda[rows[i].k];
    acc(i) = std::abs(D(l.tangent));
    cone_s(i) = D(c.static_friction) * D(l.normal);
    cone_d(i) = D(c.dynamic_friction) * D(l.normal);
    const RigidBody& b = *rows[i].body;
    const Vec3 pb_prev = c.body < 0 ? rows[i].f.p : Vec3(b.x_prev + b.q_prev * (b.q.conjugate() * rows[i].f.rw));
    const Vec3D rel = ((s.x[p] - s.x_prev[p]) - (rows[i].f.p - pb_prev)).cast<D>();
    for (int a = 0; a < 2; ++a) {
      g(2 * i + a) = rows[i].t[a].dot(rel);
      for (int j = 0; j < n; ++j)
        for (int bb = 0; bb < 2; ++bb) {
          const D tt = rows[i].t[a].dot(rows[j].t[bb]);
          D kk = wp * tt;
          if (rows[i].dynamic && rows[i].body == rows[j].body)
            kk += D(b.inv_mass) * tt + rows[i].rt[a].dot(b.inv_inertia.cast<D>().cwiseProduct(rows[j].rt[bb]));
          K(2 * i + a, 2 * j + bb) = kk;
        }
    }
  }
  if (!g.allFinite() || !K.allFinite()) return false;

  // Solve with the sliding contacts held; at most one more slides per round.
  bool held[kMaxJointContacts] = {};
  u.setZero();
  for (int round = 0; round <= n; ++round) {
    int fr[2 * kMaxJointContacts], nf = 0;
    for (int i = 0; i < n; ++i)
      if (!held[i]) fr[nf++] = 2 * i, fr[nf++] = 2 * i + 1;
    if (nf == 0) break;
    MatT Kf(nf, nf);
    VecT bf(nf);
    for (int a = 0; a < nf; ++a) {
      D held_part = 0;
      for (int i = 0; i < n; ++i)
        if (held[i]) held_part += K(fr[a], 2 * i) * u(2 * i) + K(fr[a], 2 * i + 1) * u(2 * i + 1);
      bf(a) = -g(fr[a]) - held_part;
      for (int b = 0; b < nf; ++b) Kf(a, b) = K(fr[a], fr[b]);
    }
    const Eigen::LDLT<MatT> ldlt(Kf);
    if (ldlt.info() != Eigen::Success) return false;
    const VecT x = ldlt.solve(bf);
    if (!x.allFinite()) return false;
    for (int a = 0; a < nf; ++a) u(fr[a]) = x(a);
    // The free contact farthest outside its static cone slides.
    int worst = -1;
    D worst_ratio = 1;
    for (int i = 0; i < n; ++i) {
      if (held[i]) continue;
      const D total = acc(i) + std::hypot(u(2 * i), u(2 * i + 1));
      if (total <= cone_s(i)) continue;
      const D ratio = cone_s(i) > D(0) ? total / cone_s(i) : std::numeric_limits<D>::infinity();
      if (worst < 0 || ratio > worst_ratio) worst = i, worst_ratio = ratio;
    }
    if (worst < 0) break;
    const D len = std::hypot(u(2 * worst), u(2 * worst + 1));
    const D scale = len > D(0) ? std::max(cone_d(worst) - acc(worst), D(0)) / len : D(0);
    u(2 * worst) *= scale;
    u(2 * worst + 1) *= scale;
    held[worst] = true;
  }

  // Apply, as the normal parts: the particle once, each body by its impulse.
  Vec3D dxp = Vec3D::Zero();
  for (int i = 0; i < n; ++i) {
    ContactLambda& l = s.contact_lambda[rows[i].k];
    const Vec3D imp = u(2 * i) * rows[i].t[0] + u(2 * i + 1) * rows[i].t[1];
    l.tangent = Real(acc(i) + imp.norm());
    l.joint = true;
    dxp += imp;
    const Vec3 pi = (-imp).cast<Real>();
    apply_position_impulse(*rows[i].body, rows[i].f.rw, pi);
    record_push(s, s.contacts[rows[i].k].body, pi);
  }
  s.x[p] += (wp * dxp).cast<Real>();
  return true;
}

}  // namespace xpbd::rigid
