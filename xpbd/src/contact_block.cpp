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
// Attachments. The particle's attachments (BodyAttachment: C = x_p - p_b,
// three rows, compliance a) join the block as equality rows, always active:
// rhs = -C - a lambda with the attachment's vector multiplier
// (State::attachment_impulse). Why: an attached particle has no contact with
// its own body, and a third body that presses on it moves the light
// particle, not the bar it hangs from: the attachment, solved earlier in the
// sweep, pulls it back only in the next sweep, and the last contact pushed
// an attached particle 16 mm into its bar (docs/squeeze.md). With the rows
// in the block the particle is a spacer between the two bodies.
//
// Bodies held by the world. A body the block pushes into its own support
// (a crate on the floor under the cloth, pressed by a box on the cloth) is
// held, not moved: the world takes that push (supported_against). Shared by
// inverse masses instead, the crate took most of each correction, its
// contacts with the floor (solved first and last in the sweep) pushed it
// back, and the box kept the overlap, which came out over the next substeps
// as an upward speed: a 100 kg box that landed at 1.8 m/s on a cloth on a
// 20 kg crate bounced back at 1.27 m/s at 45 substeps (docs/squeeze-crate.md).
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
// The rows of the attachments a block takes (3 each).
constexpr int kAttRows = 3 * kMaxJointAttachments;
constexpr int kMaxRows = kMaxJointContacts + kAttRows;
using MatK = Eigen::Matrix<D, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxRows, kMaxRows>;
using VecK = Eigen::Matrix<D, Eigen::Dynamic, 1, 0, kMaxRows, 1>;
using Vec3D = Eigen::Matrix<D, 3, 1>;
// The friction's system: two tangent directions per contact.
constexpr int kMaxTRows = 2 * kMaxJointContacts + kAttRows;
using MatT = Eigen::Matrix<D, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxTRows, kMaxTRows>;
using VecT = Eigen::Matrix<D, Eigen::Dynamic, 1, 0, kMaxTRows, 1>;

// One row of a block: a unit direction d (world) along which the particle
// is pushed by +dl and its body by -dl at lever arm r.
struct Dir {
  Vec3D d = Vec3D::Zero();
  Vec3D rd = Vec3D::Zero();  // (r x d) in the body frame, for the angular terms
  const RigidBody* body = nullptr;
  bool dynamic = false;
};

Dir make_dir(const RigidBody& b, bool dynamic, const Vec3& rw, const Vec3D& d) {
  return {d, (b.q.conjugate() * rw.cross(d.cast<Real>())).cast<D>(), &b, dynamic};
}

// How a push along row j changes row i's constraint:
// w_p d_i.d_j + [same dynamic body] (d_i.d_j / m + (r_i x d_i).I^-1 (r_j x d_j)).
D coupling(D wp, const Dir& a, const Dir& b) {
  const D dd = a.d.dot(b.d);
  D k = wp * dd;
  if (a.dynamic && a.body == b.body)
    k += D(a.body->inv_mass) * dd + a.rd.dot(a.body->inv_inertia.cast<D>().cwiseProduct(b.rd));
  return k;
}

// One of the particle's attachments, at the current poses.
struct Att {
  std::size_t k = 0;
  RigidBody* body = nullptr;
  bool dynamic = false;
  Vec3 rw = Vec3::Zero();
  Vec3D c = Vec3D::Zero();  // C = x_p - p_b
  D at = 0;                 // compliance / h^2
};

// The first kMaxJointAttachments attachments of the particle of contact
// `head` (the others keep their own stage), with their three rows each
// appended to `dirs` from index `first`.
int gather_attachments(State& s, std::size_t head, D inv_h2, Att att[], Dir dirs[], int first) {
  int na = 0;
  const Index p = s.contacts[head].particle;
  for (Index a = s.contact_attachment[head]; a >= 0 && na < kMaxJointAttachments;
       a = s.attachment_next[static_cast<std::size_t>(a)]) {
    const BodyAttachment& ba = s.attachments[static_cast<std::size_t>(a)];
    Att& t = att[na];
    t.k = static_cast<std::size_t>(a);
    t.body = &body_or_world(s, ba.body);
    t.dynamic = ba.body >= 0 && t.body->inv_mass > Real(0);
    t.rw = ba.body < 0 ? Vec3::Zero() : Vec3(t.body->q * ba.r);
    const Vec3 pb = ba.body < 0 ? ba.r : Vec3(t.body->x + t.rw);
    t.c = (s.x[p] - pb).cast<D>();
    t.at = D(ba.compliance) * inv_h2;
    for (int e = 0; e < 3; ++e) dirs[first + 3 * na + e] = make_dir(*t.body, t.dynamic, t.rw, Vec3D::Unit(e));
    ++na;
  }
  return na;
}

// Applies the change dl of an attachment's three rows: to the particle's
// move (summed by the caller), the body, and the multipliers.
void apply_attachment(State& s, const Att& t, const Vec3D& dl, Vec3D& dxp) {
  const D len = t.c.norm();
  if (len > D(0)) s.attachment_lambda[t.k] += Real(dl.dot(t.c) / len);
  s.attachment_impulse[t.k] += dl.cast<Real>();
  dxp += dl;
  apply_position_impulse(*t.body, t.rw, -dl.cast<Real>());
}

// Whether dynamic body `b`, pushed at world point `at` along `push`, rests
// on the static world against that push, so that the world, not the body,
// takes it: the push lies inside the friction cone of the body's contacts
// with static bodies that touch (pushed in this substep, or at or inside
// the surface; State::world_contacts), and its line meets their support
// polygon (the convex hull of those points, seen along the normal), so that
// it turns the body about no edge of it. Such a body is held in the joint
// blocks below. `lean` > 0: the push may lean off its direction by up to
// atan(lean) (a friction impulse of up to lean times the push beside it),
// and every such push must lie inside the cone.
bool supported_against(const State& s, Index b, const Vec3& at, const Vec3& push, Real lean = 0) {
  const Real len = push.norm();
  if (!(len > Real(0))) return false;
  const RigidBody& body = s.bodies[static_cast<std::size_t>(b)];
  Vec3 n = Vec3::Zero();
  constexpr int kMaxPoints = 16;
  Vec3 pts[kMaxPoints];
  int np = 0;
  const auto bi = static_cast<std::size_t>(b);
  if (bi + 1 >= s.world_contact_begin.size()) return false;
  for (Index j = s.world_contact_begin[bi]; j < s.world_contact_begin[bi + 1] && np < kMaxPoints; ++j) {
    const auto k = static_cast<std::size_t>(s.world_contact_of[static_cast<std::size_t>(j)]);
    const BodyWorldContact& c = s.world_contacts[k];
    const Real into = -c.n.dot(push);  // > 0: into the surface
    const Real side = (push + into * c.n).norm();
    // The push leaning by atan(lean) at worst, away from the normal, inside
    // the cone: tan(a + b) = (side / into + lean) / (1 - lean side / into)
    // at most mu, and a + b below a right angle.
    const Real mu = std::max(c.friction, Real(1e-6));
    const Real rest = into - lean * side;
    if (!(into > Real(0)) || !(rest > Real(0)) || side + lean * into > mu * rest) continue;
    const Vec3 pw = body.x + body.q * c.r;
    // Touching: it pushed in this substep, or the point is at or in the surface.
    if (!(s.world_contact_lambda[k].normal > Real(0)) && !(c.n.dot(pw - c.p) - s.world_contact_slack[k] <= Real(0)))
      continue;
    if (np == 0) n = c.n;
    else if (n.dot(c.n) < Real(0.999)) continue;  // one support plane (the first)
    pts[np++] = pw;
  }
  if (np == 0) return false;
  // 2D coordinates in the support plane; the push line meets it at q.
  const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
  const Real t = n.dot(pts[0] - at) / n.dot(push);
  const Vec3 q = at + t * push;
  if (!q.allFinite()) return false;
  const Real tol = Real(1e-6) + kDegenerateRel * (q.norm() + body.x.norm());
  Real px[kMaxPoints], py[kMaxPoints];
  for (int i = 0; i < np; ++i) px[i] = u.dot(pts[i] - q), py[i] = v.dot(pts[i] - q);
  // Inside the hull: the origin is on the inner side of every hull edge. The
  // hull by gift wrapping (at most 16 points).
  const auto dist_to_segment = [&](int i, int j) {
    const Real ex = px[j] - px[i], ey = py[j] - py[i], l2 = ex * ex + ey * ey;
    const Real f = l2 > Real(0) ? std::clamp(-(px[i] * ex + py[i] * ey) / l2, Real(0), Real(1)) : Real(0);
    return std::hypot(px[i] + f * ex, py[i] + f * ey);
  };
  int start = 0;
  for (int i = 1; i < np; ++i)
    if (px[i] < px[start] || (px[i] == px[start] && py[i] < py[start])) start = i;
  int hull[kMaxPoints + 1], nh = 0, cur = start;
  do {
    hull[nh++] = cur;
    int next = (cur + 1) % np;
    for (int i = 0; i < np; ++i) {
      const Real cr = (px[next] - px[cur]) * (py[i] - py[cur]) - (py[next] - py[cur]) * (px[i] - px[cur]);
      if (cr < Real(0)) next = i;
    }
    cur = next;
  } while (cur != start && nh < kMaxPoints);
  if (nh < 3) {
    Real d = std::hypot(px[hull[0]], py[hull[0]]);
    if (nh == 2) d = dist_to_segment(hull[0], hull[1]);
    return d <= tol;
  }
  for (int e = 0; e < nh; ++e) {
    const int i = hull[e], j = hull[(e + 1) % nh];
    // Counter-clockwise hull: the origin must not be to the right of i -> j
    // by more than the tolerance.
    const Real cr = (px[j] - px[i]) * (-py[i]) - (py[j] - py[i]) * (-px[i]);
    const Real el = std::hypot(px[j] - px[i], py[j] - py[i]);
    if (cr < -tol * el) return false;
  }
  return true;
}

}  // namespace

bool solve_contact_group(const Model& m, State& s, std::size_t head, Real inv_h2) {
  // Rows 0..nc-1: the contacts; then three per attachment.
  std::size_t ck[kMaxJointContacts];
  Frame fr[kMaxJointContacts];
  RigidBody* cb[kMaxJointContacts];
  bool frozen[kMaxJointContacts];
  Dir dirs[kMaxRows];
  int nc = 0;
  for (Index j = Index(head); j >= 0; j = s.contact_next[static_cast<std::size_t>(j)]) {
    if (nc == kMaxJointContacts) return false;
    const std::size_t k = static_cast<std::size_t>(j);
    const BodyContact& c = s.contacts[k];
    ck[nc] = k;
    cb[nc] = &body_or_world(s, c.body);
    fr[nc] = contact_frame(*cb[nc], c, c.body < 0, s.x[c.particle]);
    const bool dyn = c.body >= 0 && cb[nc]->inv_mass > Real(0);
    frozen[nc] = dyn && supported_against(s, c.body, fr[nc].p, -fr[nc].n);
    dirs[nc] = make_dir(*cb[nc], dyn && !frozen[nc], fr[nc].rw, fr[nc].n.cast<D>());
    ++nc;
  }
  Att att[kMaxJointAttachments];
  const int na = gather_attachments(s, head, D(inv_h2), att, dirs, nc);
  const int n = nc + 3 * na;
  const Index p = s.contacts[head].particle;
  const D wp = m.inv_mass[p];

  MatK A(n, n);
  VecK rhs(n), lambda(n);
  bool any = false;
  D scale = 0;
  for (int i = 0; i < n; ++i) {
    if (i < nc) {
      const BodyContact& c = s.contacts[ck[i]];
      const Real C = fr[i].n.dot(s.x[p] - fr[i].p) - c.thickness;
      lambda(i) = s.contact_lambda[ck[i]].normal;
      any = any || C < Real(0) || lambda(i) != D(0);
      const D at = D(c.compliance) * D(inv_h2);
      rhs(i) = -D(C) - at * lambda(i);
      A(i, i) = at;
    } else {
      const Att& t = att[(i - nc) / 3];
      const int e = (i - nc) % 3;
      lambda(i) = D(s.attachment_impulse[t.k](e));
      rhs(i) = -t.c(e) - t.at * lambda(i);
      A(i, i) = t.at;
    }
    for (int j = 0; j < n; ++j) A(i, j) = (i == j ? A(i, i) : D(0)) + coupling(wp, dirs[i], dirs[j]);
    scale = std::max({scale, std::abs(rhs(i)), std::abs(A(i, i) * lambda(i))});
  }
  if (!any) return true;  // nothing touches and nothing pushed: no change, as one by one
  if (!(scale < std::numeric_limits<D>::infinity())) return false;

  // Every active set of the contacts, largest first (the attachments' rows
  // are always active); the first that satisfies the conditions is the
  // solution.
  const D eps = std::numeric_limits<D>::epsilon();
  const D tol = D(64) * eps * (scale + D(1e-30));
  VecK dl(n);
  for (unsigned mask = (1u << nc) - 1;; --mask) {
    int act[kMaxRows], nact = 0;
    for (int i = 0; i < n; ++i) {
      if (i >= nc || (mask & (1u << i))) {
        act[nact++] = i;
        dl(i) = 0;
      } else {
        dl(i) = -lambda(i);
      }
    }
    bool ok = true;
    if (nact > 0) {
      MatK As(nact, nact);
      VecK bs(nact);
      for (int a = 0; a < nact; ++a) {
        bs(a) = rhs(act[a]) - A.row(act[a]).dot(dl);
        for (int b = 0; b < nact; ++b) As(a, b) = A(act[a], act[b]);
      }
      const Eigen::LDLT<MatK> ldlt(As);
      const auto d = ldlt.vectorD();
      const D dmax = d.cwiseAbs().maxCoeff();
      ok = ldlt.info() == Eigen::Success && (d.array() > D(64) * eps * dmax).all();
      if (ok) {
        const VecK x = ldlt.solve(bs);
        for (int a = 0; a < nact; ++a) {
          dl(act[a]) = x(a);
          ok = ok && std::isfinite(x(a)) && (act[a] >= nc || lambda(act[a]) + x(a) >= -tol);
        }
      }
    }
    if (ok)
      for (int i = 0; i < nc; ++i)
        if (!(mask & (1u << i))) ok = ok && A.row(i).dot(dl) - rhs(i) >= -tol;
    if (ok) break;
    if (mask == 0) return false;
  }

  // Apply: the particle once (its move summed in double: for a spacer the
  // pushes nearly cancel), each body by its row's impulse.
  Vec3D dxp = Vec3D::Zero();
  for (int i = 0; i < nc; ++i) {
    ContactLambda& l = s.contact_lambda[ck[i]];
    const D ln = std::max(lambda(i) + dl(i), D(0));
    const D dd = ln - D(l.normal);
    const Real d = Real(dd);
    l.normal = Real(ln);
    dxp += dd * dirs[i].d;
    if (!frozen[i]) apply_position_impulse(*cb[i], fr[i].rw, -d * fr[i].n);
    record_push(s, s.contacts[ck[i]].body, -d * fr[i].n);
  }
  for (int t = 0; t < na; ++t) apply_attachment(s, att[t], dl.segment<3>(nc + 3 * t), dxp);
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
bool solve_friction_group(const Model& m, State& s, std::size_t head, Real inv_h2) {
  // Rows 0..2nc-1: two per contact that pushes and has friction; then
  // three per attachment (equality rows, as in the normal block).
  std::size_t ck[kMaxJointContacts];
  Frame fr[kMaxJointContacts];
  RigidBody* cb[kMaxJointContacts];
  bool world_held[kMaxJointContacts];
  Dir dirs[kMaxTRows];
  int nc = 0;
  const Index p = s.contacts[head].particle;
  for (Index j = Index(head); j >= 0; j = s.contact_next[static_cast<std::size_t>(j)]) {
    const std::size_t k = static_cast<std::size_t>(j);
    const BodyContact& c = s.contacts[k];
    if (s.contact_lambda[k].normal <= Real(0)) continue;
    if (c.static_friction <= Real(0) && c.dynamic_friction <= Real(0)) continue;
    if (nc == kMaxJointContacts) return false;
    ck[nc] = k;
    cb[nc] = &body_or_world(s, c.body);
    fr[nc] = contact_frame(*cb[nc], c, c.body < 0, s.x[p]);
    // A body held against the contact's push (as in the normal block) is
    // held against its friction too when the push with any friction its
    // static cone allows stays inside its own contacts' cones with the
    // static world: the world then takes that friction.
    world_held[nc] = c.body >= 0 && cb[nc]->inv_mass > Real(0) &&
                     supported_against(s, c.body, fr[nc].p, -fr[nc].n, c.static_friction);
    const bool dynamic = c.body >= 0 && cb[nc]->inv_mass > Real(0) && !world_held[nc];
    const Vec3D nd = fr[nc].n.cast<D>();
    const Vec3D t0 = nd.unitOrthogonal();
    dirs[2 * nc] = make_dir(*cb[nc], dynamic, fr[nc].rw, t0);
    dirs[2 * nc + 1] = make_dir(*cb[nc], dynamic, fr[nc].rw, nd.cross(t0));
    ++nc;
  }
  if (nc == 0) return false;
  Att att[kMaxJointAttachments];
  const int na = gather_attachments(s, head, D(inv_h2), att, dirs, 2 * nc);
  if (nc + na < 2) return false;  // one by one: the same as the particle's lone contact
  const D wp = m.inv_mass[p];

  const int n2 = 2 * nc, n = n2 + 3 * na;
  MatT K(n, n);
  VecT g(n), u(n);
  VecK cone_s(nc), cone_d(nc), acc(nc);
  for (int i = 0; i < nc; ++i) {
    const BodyContact& c = s.contacts[ck[i]];
    const ContactLambda& l = s.contact_lambda[ck[i]];
    acc(i) = std::abs(D(l.tangent));
    cone_s(i) = D(c.static_friction) * D(l.normal);
    cone_d(i) = D(c.dynamic_friction) * D(l.normal);
    const RigidBody& b = *cb[i];
    const Vec3 pb_prev = c.body < 0 ? fr[i].p : Vec3(b.x_prev + b.q_prev * (b.q.conjugate() * fr[i].rw));
    const Vec3D rel = ((s.x[p] - s.x_prev[p]) - (fr[i].p - pb_prev)).cast<D>();
    for (int a = 0; a < 2; ++a) g(2 * i + a) = dirs[2 * i + a].d.dot(rel);
  }
  for (int t = 0; t < na; ++t)
    for (int e = 0; e < 3; ++e) {
      const int i = n2 + 3 * t + e;
      g(i) = att[t].c(e) + att[t].at * D(s.attachment_impulse[att[t].k](e));
    }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) K(i, j) = coupling(wp, dirs[i], dirs[j]);
    if (i >= n2) K(i, i) += att[(i - n2) / 3].at;
  }
  if (!g.allFinite() || !K.allFinite()) return false;

  // Solve with the sliding contacts held; at most one more slides per round.
  bool held[kMaxJointContacts] = {};
  u.setZero();
  for (int round = 0; round <= nc; ++round) {
    int fr_[kMaxTRows], nf = 0;
    for (int i = 0; i < nc; ++i)
      if (!held[i]) fr_[nf++] = 2 * i, fr_[nf++] = 2 * i + 1;
    for (int i = n2; i < n; ++i) fr_[nf++] = i;
    if (nf == 0) break;  // every contact slides, and no attachment
    MatT Kf(nf, nf);
    VecT bf(nf);
    for (int a = 0; a < nf; ++a) {
      D held_part = 0;
      for (int i = 0; i < nc; ++i)
        if (held[i]) held_part += K(fr_[a], 2 * i) * u(2 * i) + K(fr_[a], 2 * i + 1) * u(2 * i + 1);
      bf(a) = -g(fr_[a]) - held_part;
      for (int b = 0; b < nf; ++b) Kf(a, b) = K(fr_[a], fr_[b]);
    }
    const Eigen::LDLT<MatT> ldlt(Kf);
    if (ldlt.info() != Eigen::Success) return false;
    const VecT x = ldlt.solve(bf);
    if (!x.allFinite()) return false;
    for (int a = 0; a < nf; ++a) u(fr_[a]) = x(a);
    // The free contact farthest outside its static cone slides.
    int worst = -1;
    D worst_ratio = 1;
    for (int i = 0; i < nc; ++i) {
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
  for (int i = 0; i < nc; ++i) {
    ContactLambda& l = s.contact_lambda[ck[i]];
    const Vec3D imp = u(2 * i) * dirs[2 * i].d + u(2 * i + 1) * dirs[2 * i + 1].d;
    l.tangent = Real(acc(i) + imp.norm());
    l.joint = true;
    dxp += imp;
    const Vec3 pi = (-imp).cast<Real>();
    if (!world_held[i]) apply_position_impulse(*cb[i], fr[i].rw, pi);
    record_push(s, s.contacts[ck[i]].body, pi);
  }
  for (int t = 0; t < na; ++t) apply_attachment(s, att[t], u.segment<3>(n2 + 3 * t), dxp);
  s.x[p] += (wp * dxp).cast<Real>();
  return true;
}

}  // namespace xpbd::rigid
