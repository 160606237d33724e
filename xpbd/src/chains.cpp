// Direct solve along chains (chains.hpp, StepConfig::direct_chains).
#include "chains_solve.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rigid_internal.hpp"
#include "xpbd/constraints.hpp"
#include "xpbd/model.hpp"
#include "xpbd/state.hpp"

namespace xpbd {

Chains find_chains(const std::vector<Distance>& elements, Index num_particles) {
  Chains out;
  out.num_distance = elements.size();
  const auto np = static_cast<std::size_t>(std::max<Index>(num_particles, 0));
  // Elements per particle (CSR), counting every element: a particle in a
  // damped element as well is an end.
  std::vector<Index> first(np + 1, 0), adj;
  for (const Distance& e : elements)
    for (Index p : e.p)
      if (p >= 0 && static_cast<std::size_t>(p) < np) ++first[static_cast<std::size_t>(p) + 1];
  for (std::size_t i = 0; i < np; ++i) first[i + 1] += first[i];
  adj.resize(static_cast<std::size_t>(first[np]));
  {
    std::vector<Index> cursor(first.begin(), first.end() - 1);
    for (std::size_t k = 0; k < elements.size(); ++k)
      for (Index p : elements[k].p)
        if (p >= 0 && static_cast<std::size_t>(p) < np)
          adj[static_cast<std::size_t>(cursor[static_cast<std::size_t>(p)]++)] = static_cast<Index>(k);
  }
  auto eligible = [&](Index k) {
    const Distance& e = elements[static_cast<std::size_t>(k)];
    return e.mat.damping == Real(0) && e.p[0] != e.p[1];
  };
  auto degree = [&](Index p) { return first[static_cast<std::size_t>(p) + 1] - first[static_cast<std::size_t>(p)]; };
  // Inner particle: in exactly two elements, both eligible.
  auto inner = [&](Index p) {
    if (degree(p) != 2) return false;
    const auto b = static_cast<std::size_t>(first[static_cast<std::size_t>(p)]);
    return eligible(adj[b]) && eligible(adj[b + 1]);
  };
  auto other = [&](Index k, Index p) {
    const Distance& e = elements[static_cast<std::size_t>(k)];
    return e.p[0] == p ? e.p[1] : e.p[0];
  };
  std::vector<char> used(elements.size(), 0);
  // Walks from end particle p along eligible element k until the path
  // reaches a particle that is not inner.
  for (Index p = 0; p < static_cast<Index>(np); ++p) {
    if (inner(p)) continue;
    for (Index a = first[static_cast<std::size_t>(p)]; a < first[static_cast<std::size_t>(p) + 1]; ++a) {
      Index k = adj[static_cast<std::size_t>(a)];
      if (used[static_cast<std::size_t>(k)] || !eligible(k)) continue;
      const std::size_t e0 = out.element.size(), p0 = out.particle.size();
      Index q = p;
      out.particle.push_back(q);
      for (;;) {
        used[static_cast<std::size_t>(k)] = 1;
        out.element.push_back(k);
        q = other(k, q);
        out.particle.push_back(q);
        if (!inner(q)) break;
        const auto b = static_cast<std::size_t>(first[static_cast<std::size_t>(q)]);
        k = adj[b] == k ? adj[b + 1] : adj[b];
        if (used[static_cast<std::size_t>(k)]) break;  // cannot happen from an end; kept as a guard
      }
      // One element: the sweep solves it exactly. A loop back to the particle
      // it started from: its first and last rows share that particle, which
      // a tridiagonal system cannot hold.
      if (out.element.size() - e0 < 2 || q == p) {
        out.element.resize(e0);
        out.particle.resize(p0);
        continue;
      }
      out.begin.push_back(static_cast<Index>(out.element.size()));
    }
  }
  // Whatever eligible element is left is on a closed loop: not a chain.
  if (out.size() > 0) {
    out.end_of.assign(np, -1);
    for (Index c = 0; c < out.size(); ++c) {
      const auto b = static_cast<std::size_t>(out.begin[static_cast<std::size_t>(c)] + c);
      const auto e = static_cast<std::size_t>(out.begin[static_cast<std::size_t>(c) + 1] + c);
      // An end shared by two chains (a particle where three chains meet)
      // keeps the first claim.
      Index& f = out.end_of[static_cast<std::size_t>(out.particle[b])];
      if (f < 0) f = 2 * c;
      Index& l = out.end_of[static_cast<std::size_t>(out.particle[e])];
      if (l < 0) l = 2 * c + 1;
    }
  }
  return out;
}

namespace detail {

void chains_begin_step(const Model& m, State& s) {
  const Chains& ch = m.chains;
  ChainScratch& cs = s.chain;
  cs.end_attachment.assign(static_cast<std::size_t>(2 * ch.size()), -1);
  for (std::size_t k = 0; k < s.attachments.size(); ++k) {
    const Index slot = ch.end_of.empty() ? -1 : ch.end_of[static_cast<std::size_t>(s.attachments[k].particle)];
    if (slot < 0) continue;
    Index& a = cs.end_attachment[static_cast<std::size_t>(slot)];
    a = a == -1 ? static_cast<Index>(k) : -2;  // two or more: none is taken
  }
  for (Index c = 0; c < ch.size(); ++c) {
    Index& f = cs.end_attachment[static_cast<std::size_t>(2 * c)];
    Index& l = cs.end_attachment[static_cast<std::size_t>(2 * c + 1)];
    if (f < -1) f = -1;
    if (l < -1) l = -1;
    if (f >= 0 && l >= 0) {
      const Index bf = s.attachments[static_cast<std::size_t>(f)].body;
      if (bf >= 0 && bf == s.attachments[static_cast<std::size_t>(l)].body) f = -1;
    }
  }
  std::size_t rows = 0;
  for (Index c = 0; c < ch.size(); ++c)
    rows = std::max(rows, static_cast<std::size_t>(ch.begin[static_cast<std::size_t>(c) + 1] -
                                                   ch.begin[static_cast<std::size_t>(c)]) + 2);
  cs.n.resize(rows);
  cs.diag.resize(rows);
  cs.off.resize(rows);
  cs.rhs.resize(rows);
  cs.c.resize(rows);
  cs.d.resize(rows);
}

namespace {

using rigid::detail::apply_position_impulse;
using rigid::detail::body_or_world;

// A pivot below this fraction of its row's diagonal is taken as singular.
constexpr Real kPivot = Real(1024) * std::numeric_limits<Real>::epsilon();

// One chain's system. Row r joins node r and node r + 1: node 0 is the
// front attachment's body point when there is one, then the chain's
// particles in order, then the back attachment's body point.
class ChainSystem {
 public:
  ChainSystem(const Model& m, State& s, Index c, bool stream, Real inv_h2)
      : m_(m), s_(s), cs_(s.chain), stream_(stream), inv_h2_(inv_h2) {
    const Chains& ch = m.chains;
    eb_ = static_cast<std::size_t>(ch.begin[static_cast<std::size_t>(c)]);
    links_ = static_cast<std::size_t>(ch.begin[static_cast<std::size_t>(c) + 1]) - eb_;
    parts_ = ch.particle.data() + eb_ + static_cast<std::size_t>(c);
    front_ = cs_.end_attachment[static_cast<std::size_t>(2 * c)];
    back_ = cs_.end_attachment[static_cast<std::size_t>(2 * c + 1)];
    lead_ = front_ >= 0 ? 1 : 0;
    rows_ = links_ + lead_ + (back_ >= 0 ? 1 : 0);
    // Attachment rows (rest length 0) measure their residual against the
    // chain's first element.
    chain_rest_ = m.get<Distance>()[static_cast<std::size_t>(ch.element[eb_])].rest;
  }

  // Fills each row's direction, diagonal and right-hand side at the current
  // positions; returns the largest residual |C + at lambda| / rest.
  Real assemble() {
    Real worst = 0;
    for (std::size_t r = 0; r < rows_; ++r) {
      const Vec3 a = node_position(r), b = node_position(r + 1);
      const bool attachment = is_attachment_row(r);
      Real rest = 0, compliance = 0;
      if (attachment) {
        compliance = attachment_of_row(r).compliance;
      } else {
        const Distance& e = element_of_row(r);
        rest = e.rest;
        compliance = e.mat.compliance;
      }
      const Vec3 d = b - a;
      const Real len = d.norm();
      const Real at = compliance * inv_h2_;
      const bool defined = attachment ? len > Real(0) : len > kDegenerateRel * rest;
      const Vec3 n = defined ? Vec3(d / len) : Vec3(Vec3::Zero());
      Real diag = node_inv_mass(r, n) + node_inv_mass(r + 1, n) + at;
      Real rhs = -(len - rest) - at * lambda_of(r);
      if (!defined || !(diag > Real(0))) {  // no direction, or nothing can move: dlambda = 0
        cs_.n[r] = Vec3::Zero();
        diag = 1;
        rhs = 0;
      } else {
        cs_.n[r] = n;
      }
      cs_.diag[r] = diag;
      cs_.rhs[r] = rhs;
      worst = std::max(worst, std::abs(rhs) / (rest > Real(0) ? rest : chain_rest_));
    }
    return worst;
  }

  // Solves for dlambda (into cs.d) with the Thomas algorithm: the matrix is
  // symmetric positive semi-definite, the off-diagonal of rows r and r + 1
  // is -w n_r . n_{r+1} for the particle they share. False if singular.
  bool solve() {
    for (std::size_t r = 0; r + 1 < rows_; ++r)
      cs_.off[r] = -particle_inv_mass(r + 1) * cs_.n[r].dot(cs_.n[r + 1]);
    Real piv = cs_.diag[0];
    cs_.c[0] = rows_ > 1 ? cs_.off[0] / piv : Real(0);
    cs_.d[0] = cs_.rhs[0] / piv;
    for (std::size_t r = 1; r < rows_; ++r) {
      piv = cs_.diag[r] - cs_.off[r - 1] * cs_.c[r - 1];
      if (!(piv > kPivot * cs_.diag[r])) return false;
      cs_.c[r] = r + 1 < rows_ ? cs_.off[r] / piv : Real(0);
      cs_.d[r] = (cs_.rhs[r] - cs_.off[r - 1] * cs_.d[r - 1]) / piv;
    }
    for (std::size_t r = rows_ - 1; r-- > 0;) cs_.d[r] -= cs_.c[r] * cs_.d[r + 1];
    for (std::size_t r = 0; r < rows_; ++r)
      if (!std::isfinite(cs_.d[r])) return false;  // cannot happen for finite input; never write a NaN
    return true;
  }

  // Moves the nodes by W J^T dlambda and adds dlambda to the multipliers:
  // particle node i by w_i (n_{i-1} dl_{i-1} - n_i dl_i), a body point by
  // its row's gradient times dl as a position impulse.
  void apply() {
    for (std::size_t node = lead_; node <= lead_ + links_; ++node) {
      const Real w = particle_inv_mass(node);
      if (w == Real(0)) continue;
      Vec3 g = Vec3::Zero();
      if (node > 0) g += cs_.d[node - 1] * cs_.n[node - 1];
      if (node < rows_) g -= cs_.d[node] * cs_.n[node];
      s_.x[static_cast<std::size_t>(parts_[node - lead_])] += w * g;
    }
    // An attachment's own direction (solve_attachments) is particle minus
    // body point: +n of the front row, -n of the back row.
    if (front_ >= 0) {
      const Vec3 dn = cs_.d[0] * cs_.n[0];
      apply_position_impulse(body_or_world(s_, attachment_of_row(0).body), lever(0), -dn);
      s_.attachment_impulse[static_cast<std::size_t>(front_)] += dn;
    }
    if (back_ >= 0) {
      const Vec3 dn = cs_.d[rows_ - 1] * cs_.n[rows_ - 1];
      apply_position_impulse(body_or_world(s_, attachment_of_row(rows_ - 1).body), lever(rows_), dn);
      s_.attachment_impulse[static_cast<std::size_t>(back_)] -= dn;
    }
    for (std::size_t r = 0; r < rows_; ++r) lambda_of(r) += cs_.d[r];
  }

 private:
  bool is_body_node(std::size_t node) const {
    return (node == 0 && front_ >= 0) || node > lead_ + links_;
  }
  bool is_attachment_row(std::size_t r) const { return r < lead_ || r >= lead_ + links_; }
  const BodyAttachment& attachment_of_row(std::size_t r) const {
    return s_.attachments[static_cast<std::size_t>(r < lead_ ? front_ : back_)];
  }
  const BodyAttachment& attachment_of_node(std::size_t node) const {
    return s_.attachments[static_cast<std::size_t>(node == 0 && front_ >= 0 ? front_ : back_)];
  }
  const Distance& element_of_row(std::size_t r) const {
    return m_.get<Distance>()[static_cast<std::size_t>(m_.chains.element[eb_ + r - lead_])];
  }
  Real particle_inv_mass(std::size_t node) const {
    return m_.inv_mass[static_cast<std::size_t>(parts_[node - lead_])];
  }
  // World lever arm of a body node's attachment point (zero for a fixed
  // world point).
  Vec3 lever(std::size_t node) const {
    const BodyAttachment& a = attachment_of_node(node);
    return a.body < 0 ? Vec3(Vec3::Zero()) : Vec3(body_or_world(s_, a.body).q * a.r);
  }
  Vec3 node_position(std::size_t node) const {
    if (!is_body_node(node)) return s_.x[static_cast<std::size_t>(parts_[node - lead_])];
    const BodyAttachment& a = attachment_of_node(node);
    return a.body < 0 ? a.r : Vec3(body_or_world(s_, a.body).x + lever(node));
  }
  // Inverse mass of a node along unit n (a body's includes its rotation).
  Real node_inv_mass(std::size_t node, const Vec3& n) const {
    if (!is_body_node(node)) return particle_inv_mass(node);
    return rigid::inv_mass_along(body_or_world(s_, attachment_of_node(node).body), lever(node), n);
  }
  Real& lambda_of(std::size_t r) {
    if (is_attachment_row(r)) return s_.attachment_lambda[static_cast<std::size_t>(r < lead_ ? front_ : back_)];
    const std::size_t j = eb_ + r - lead_;
    if (stream_) return s_.stream_lambda[static_cast<std::size_t>(m_.chains.stream_slot[j])];
    return s_.lambdas<Distance>()[static_cast<std::size_t>(m_.chains.element[j])];
  }

  const Model& m_;
  State& s_;
  ChainScratch& cs_;
  bool stream_;
  Real inv_h2_;
  std::size_t eb_ = 0, links_ = 0, lead_ = 0, rows_ = 0;
  const Index* parts_ = nullptr;
  Index front_ = -1, back_ = -1;
  Real chain_rest_ = 0;
};

}  // namespace

void chains_solve(const Model& m, State& s, Real h, bool stream, int passes, Real tol) {
  const Real inv_h2 = Real(1) / (h * h);
  for (Index c = 0; c < m.chains.size(); ++c) {
    ChainSystem sys(m, s, c, stream, inv_h2);
    newton_passes(sys, passes, tol);
  }
}

}  // namespace detail
}  // namespace xpbd
