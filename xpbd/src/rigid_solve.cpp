#include "xpbd/rigid_solve.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/LU>

#include "xpbd/constraints_contact.hpp"
#include "xpbd/error.hpp"
#include "contact_block.hpp"
#include "rigid_checks.hpp"
#include "rigid_internal.hpp"

namespace xpbd::rigid {

using namespace detail;

namespace {

// Chains of the contacts of each particle, and the first contacts of each
// edge contact's particles (contact_last is all -1 between calls: only the
// entries set here are reset).
void build_contact_chains(const Model& m, State& s) {
  const std::size_t nc = s.contacts.size();
  s.contact_lambda.resize(nc);
  s.contact_head.resize(nc);
  s.contact_next.resize(nc);
  s.contact_last.resize(static_cast<std::size_t>(m.num_particles()), -1);
  for (std::size_t k = 0; k < nc; ++k) {
    Index& last = s.contact_last[static_cast<std::size_t>(s.contacts[k].particle)];
    s.contact_next[k] = -1;
    s.contact_head[k] = last < 0 ? Index(k) : s.contact_head[static_cast<std::size_t>(last)];
    if (last >= 0) s.contact_next[static_cast<std::size_t>(last)] = Index(k);
    last = Index(k);
  }
  // Each edge contact's particles' first contacts.
  s.edge_contact_head.resize(s.edge_contacts.size());
  for (std::size_t k = 0; k < s.edge_contacts.size(); ++k)
    for (int e = 0; e < 2; ++e) {
      const Index last = s.contact_last[static_cast<std::size_t>(s.edge_contacts[k].p[e])];
      s.edge_contact_head[k][e] = last < 0 ? Index(-1) : s.contact_head[static_cast<std::size_t>(last)];
    }
  for (const BodyContact& c : s.contacts) s.contact_last[static_cast<std::size_t>(c.particle)] = -1;
  // The attachments of each particle, first to last, and each contact's
  // first attachment.
  const std::size_t na = s.attachments.size();
  s.attachment_next.resize(na);
  for (std::size_t a = na; a-- > 0;) {
    Index& first = s.contact_last[static_cast<std::size_t>(s.attachments[a].particle)];
    s.attachment_next[a] = first;
    first = Index(a);
  }
  s.contact_attachment.resize(nc);
  for (std::size_t k = 0; k < nc; ++k)
    s.contact_attachment[k] = s.contact_last[static_cast<std::size_t>(s.contacts[k].particle)];
  for (const BodyAttachment& a : s.attachments) s.contact_last[static_cast<std::size_t>(a.particle)] = -1;
}

}  // namespace

void begin_step(const Model& m, State& s) {
  check_bodies(s, 0);
  for (std::size_t k = 0; k < s.contacts.size(); ++k) check_contact(m, s, k);
  for (std::size_t k = 0; k < s.attachments.size(); ++k) check_attachment(m, s, k);
  for (std::size_t k = 0; k < s.triangle_contacts.size(); ++k) check_triangle_contact(m, s, k);
  for (std::size_t k = 0; k < s.edge_contacts.size(); ++k) check_edge_contact(m, s, k);
  build_contact_chains(m, s);
  s.triangle_contact_lambda.resize(s.triangle_contacts.size());
  s.edge_contact_lambda.resize(s.edge_contacts.size());
  s.attachment_lambda.resize(s.attachments.size());
  s.attachment_impulse.resize(s.attachments.size(), Vec3::Zero());
  for (std::size_t k = 0; k < s.world_contacts.size(); ++k) check_world_contact(s, k);
  s.world_contact_lambda.resize(s.world_contacts.size());
  s.body_contact_impulse.assign(s.bodies.size(), Vec3::Zero());
  s.body_contact_push.assign(s.bodies.size(), Vec3::Zero());
  // An overlap with the static world that the step starts with is left to
  // the host (Bullet's own position correction): projected inside a
  // substep it would become a velocity of overlap / h. The contact only
  // keeps the body from going deeper: its slack is the starting overlap.
  s.world_contact_slack.resize(s.world_contacts.size());
  for (std::size_t k = 0; k < s.world_contacts.size(); ++k) {
    const BodyWorldContact& c = s.world_contacts[k];
    const RigidBody& b = s.bodies[static_cast<std::size_t>(c.body)];
    const WorldFrame f = world_frame(s, c);
    s.world_contact_slack[k] = std::min(f.n.dot(b.x + b.q * c.r - f.p), Real(0));
  }
  // Each body's contacts with the static world, for the joint block
  // (contact_block.cpp, supported_against).
  s.world_contact_begin.assign(s.bodies.size() + 1, 0);
  for (const BodyWorldContact& c : s.world_contacts)
    if (c.other < 0) ++s.world_contact_begin[static_cast<std::size_t>(c.body) + 1];
  for (std::size_t b = 0; b < s.bodies.size(); ++b) s.world_contact_begin[b + 1] += s.world_contact_begin[b];
  s.world_contact_of.resize(static_cast<std::size_t>(s.world_contact_begin.back()));
  std::vector<Index> fill(s.world_contact_begin.begin(), s.world_contact_begin.end() - 1);
  for (std::size_t k = 0; k < s.world_contacts.size(); ++k)
    if (s.world_contacts[k].other < 0)
      s.world_contact_of[static_cast<std::size_t>(fill[static_cast<std::size_t>(s.world_contacts[k].body)]++)] =
          static_cast<Index>(k);
}

void contacts_added(const Model& m, State& s, std::size_t first_contact, std::size_t first_body) {
  check_bodies(s, first_body);
  for (std::size_t k = first_contact; k < s.contacts.size(); ++k) check_contact(m, s, k);
  build_contact_chains(m, s);
  s.body_contact_impulse.resize(s.bodies.size(), Vec3::Zero());
  s.body_contact_push.resize(s.bodies.size(), Vec3::Zero());
  // The bodies added have no world contacts.
  s.world_contact_begin.resize(s.bodies.size() + 1, s.world_contact_begin.empty() ? 0 : s.world_contact_begin.back());
}

void collect_contact_impulses(State& s, Real h) {
  const Real inv_h = Real(1) / h;
  for (std::size_t k = 0; k < s.body_contact_push.size(); ++k) {
    s.body_contact_impulse[k] += inv_h * s.body_contact_push[k];
    s.body_contact_push[k] = Vec3::Zero();
  }
}

void begin_substep(const Model& m, State& s) {
  (void)m;
  std::fill(s.attachment_lambda.begin(), s.attachment_lambda.end(), Real(0));
  std::fill(s.attachment_impulse.begin(), s.attachment_impulse.end(), Vec3::Zero());
  std::fill(s.triangle_contact_lambda.begin(), s.triangle_contact_lambda.end(), ContactLambda{});
  std::fill(s.edge_contact_lambda.begin(), s.edge_contact_lambda.end(), ContactLambda{});
  std::fill(s.world_contact_lambda.begin(), s.world_contact_lambda.end(), ContactLambda{});
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    const BodyContact& c = s.contacts[k];
    const RigidBody& b = body_or_world(s, c.body);
    const Frame f = contact_frame(b, c, c.body < 0, s.x[c.particle]);
    const Vec3 vb = c.body < 0 ? Vec3::Zero() : point_velocity(b, f.rw);
    s.contact_lambda[k] = ContactLambda{Real(0), Real(0), f.n.dot(s.v[c.particle] - vb)};
  }
}

namespace {

// The torque-free part of Euler's equations, I dw/dt + w x (I w) = 0 in the
// body frame, over one substep by the implicit midpoint rule,
//   I (w' - w) + h m x (I m) = 0,  m = (w + w') / 2,
// solved by Newton's method from w' = w. The rule keeps every quadratic
// invariant of these equations, the kinetic energy and |I w|, to the
// solve's tolerance; backward Euler (Bullet's implicit form) took 56 % of
// the energy of a bar spinning at 50 rad/s out within 2 s (tests/unit/
// test_rigid_gyroscopic.cpp). Without the term w stayed fixed in the world
// while the body turned under it, so the angular momentum I_world w did
// not stay: off by 0.80 of itself within 2 s for that bar. An isotropic
// body (equal principal inertias: a sphere, a cube) has w x (I w) = 0 and is
// left alone, as is a body with an infinite inertia about some axis; so is
// a w the solve does not bring to a finite value.
constexpr int kGyroscopicNewton = 8;  // iterations at most; 2-3 at a turn of 0.1 rad per substep
void gyroscopic_step(RigidBody& b, Real h) {
  const Vec3& k = b.inv_inertia;
  if (!(k.minCoeff() > Real(0)) || (k.x() == k.y() && k.y() == k.z())) return;
  const Vec3 inertia = k.cwiseInverse();
  const Vec3 w = b.q.conjugate() * b.w;  // body frame
  const auto skew = [](const Vec3& a) {
    Mat3 m;
    m << Real(0), -a.z(), a.y(), a.z(), Real(0), -a.x(), -a.y(), a.x(), Real(0);
    return m;
  };
  Vec3 next = w;
  for (int it = 0; it < kGyroscopicNewton; ++it) {
    const Vec3 mid = Real(0.5) * (w + next);
    const Vec3 lm = inertia.cwiseProduct(mid);
    const Vec3 g = inertia.cwiseProduct(next - w) + h * mid.cross(lm);
    const Mat3 jacobian = Mat3(inertia.asDiagonal()) + (Real(0.5) * h) * (skew(mid) * inertia.asDiagonal() - skew(lm));
    const Vec3 d = jacobian.partialPivLu().solve(g);
    next -= d;
    if (!(d.norm() > kEpsilon * next.norm())) break;
  }
  if (next.allFinite()) b.w = b.q * next;
}

}  // namespace

void predict_bodies(std::vector<RigidBody>& bodies, Real h) {
  for (RigidBody& b : bodies) {
    b.x_prev = b.x;
    b.q_prev = b.q;
    if (b.inv_mass > Real(0)) {
      b.v += h * b.accel;
      b.w += h * b.ang_accel;
      gyroscopic_step(b, h);
    }
    b.x += h * b.v;
    const Quat dq(Real(0), b.w.x(), b.w.y(), b.w.z());
    b.q.coeffs() += (Real(0.5) * h) * (dq * b.q).coeffs();
    b.q.normalize();
  }
}

void solve_attachments(const Model& m, State& s, Real h) {
  const Real inv_h2 = Real(1) / (h * h);
  for (std::size_t k = 0; k < s.attachments.size(); ++k) {
    const BodyAttachment& a = s.attachments[k];
    RigidBody& b = body_or_world(s, a.body);
    const Vec3 rw = a.body < 0 ? Vec3::Zero() : Vec3(b.q * a.r);
    const Vec3 pb = a.body < 0 ? a.r : Vec3(b.x + rw);
    const Vec3 d = s.x[a.particle] - pb;
    const Real len = d.norm();
    if (!(len > Real(0))) continue;  // already on the point: direction undefined, C = 0
    const Vec3 n = d / len;
    const Real wp = m.inv_mass[a.particle];
    const Real wb = inv_mass_along(b, rw, n);
    const Real at = a.compliance * inv_h2;
    const Real den = wp + wb + at;
    if (!(den > Real(0))) continue;
    const Real dl = (-len - at * s.attachment_lambda[k]) / den;
    s.attachment_lambda[k] += dl;
    s.attachment_impulse[k] += dl * n;
    s.x[a.particle] += (wp * dl) * n;
    apply_position_impulse(b, rw, -dl * n);
  }
}

namespace {

// Normal part of contact k alone: C = n.(x_p - p_b) - thickness >= 0, the
// accumulated lambda clamped at >= 0 so the contact only pushes.
void solve_contact_normal(const Model& m, State& s, std::size_t k, Real inv_h2) {
  const BodyContact& c = s.contacts[k];
  ContactLambda& l = s.contact_lambda[k];
  RigidBody& b = body_or_world(s, c.body);
  const Index p = c.particle;
  const Real wp = m.inv_mass[p];
  const Frame f = contact_frame(b, c, c.body < 0, s.x[p]);
  const Real C = f.n.dot(s.x[p] - f.p) - c.thickness;
  if (C >= Real(0) && l.normal == Real(0)) return;
  const Real wb = inv_mass_along(b, f.rw, f.n);
  const Real at = c.compliance * inv_h2;
  const Real den = wp + wb + at;
  if (!(den > Real(0))) return;
  const Real ln = std::max(l.normal + (-C - at * l.normal) / den, Real(0));
  const Real dl = ln - l.normal;
  l.normal = ln;
  s.x[p] += (wp * dl) * f.n;
  apply_position_impulse(b, f.rw, -dl * f.n);
  record_push(s, c.body, -dl * f.n);
}

// Static friction of contact k (position level, Mueller et al. 2020 sec.
// 3.5): undo the tangential motion of the particle relative to the body
// point over this substep while the tangential multiplier stays inside the
// cone |lambda_t| <= mu_s lambda_n.
void solve_contact_friction(const Model& m, State& s, std::size_t k) {
  const BodyContact& c = s.contacts[k];
  ContactLambda& l = s.contact_lambda[k];
  if (c.static_friction <= Real(0) || l.normal <= Real(0)) return;
  RigidBody& b = body_or_world(s, c.body);
  const bool world = c.body < 0;
  const Index p = c.particle;
  const Real wp = m.inv_mass[p];
  const Frame f = contact_frame(b, c, world, s.x[p]);
  // The body's material point under the particle, at the substep's start.
  const Vec3 pb_prev = world ? f.p : Vec3(b.x_prev + b.q_prev * (b.q.conjugate() * f.rw));
  const Vec3 rel = (s.x[p] - s.x_prev[p]) - (f.p - pb_prev);
  const Vec3 dt = rel - f.n.dot(rel) * f.n;
  const Real len = dt.norm();
  if (!(len > kDegenerateRel * c.thickness) || len == Real(0)) return;
  const Vec3 t = dt / len;
  const Real wt = wp + inv_mass_along(b, f.rw, t);
  if (!(wt > Real(0))) return;
  const Real dlt = -len / wt;
  if (std::abs(l.tangent + dlt) > c.static_friction * l.normal) return;
  l.tangent += dlt;
  s.x[p] += (wp * dlt) * t;
  apply_position_impulse(b, f.rw, -dlt * t);
  record_push(s, c.body, -dlt * t);
}

}  // namespace

void solve_particle_friction(const Model& m, State& s, std::size_t head, Real inv_h2) {
  if (!solve_friction_group(m, s, head, inv_h2))
    for (Index j = Index(head); j >= 0; j = s.contact_next[static_cast<std::size_t>(j)])
      solve_contact_friction(m, s, static_cast<std::size_t>(j));
}

void solve_contacts(const Model& m, State& s, Real h) {
  const Real inv_h2 = Real(1) / (h * h);
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    const auto head = static_cast<std::size_t>(s.contact_head[k]);
    if (head != k) continue;  // solved with the first contact of its particle
    if (s.contact_next[k] < 0 && s.contact_attachment[k] < 0) {
      solve_contact_normal(m, s, k, inv_h2);
      solve_contact_friction(m, s, k);
      continue;
    }
    // Two or more contacts on one particle, or contacts of an attached
    // particle: their normal parts jointly, then their friction jointly, with
    // the particle's attachments (contact_block.cpp).
    if (!solve_contact_group(m, s, k, inv_h2))
      for (Index j = Index(k); j >= 0; j = s.contact_next[static_cast<std::size_t>(j)])
        solve_contact_normal(m, s, static_cast<std::size_t>(j), inv_h2);
    solve_particle_friction(m, s, k, inv_h2);
  }
}

namespace {

// Barycentric weights of q's projection onto triangle (x1, x2, x3), each
// clamped to [0, 1] and renormalised (a feature may lie a little outside
// the triangle it was matched with). False for a degenerate triangle.
bool triangle_weights(const Vec3& q, const Vec3& x1, const Vec3& x2, const Vec3& x3, Real w[3]) {
  const Vec3 e1 = x2 - x1, e2 = x3 - x1, d = q - x1;
  const Vec3 nn = e1.cross(e2);
  const Real a2 = nn.squaredNorm();
  if (!(a2 > Real(0))) return false;
  w[1] = std::clamp(d.cross(e2).dot(nn) / a2, Real(0), Real(1));
  w[2] = std::clamp(e1.cross(d).dot(nn) / a2, Real(0), Real(1));
  w[0] = std::max(Real(1) - w[1] - w[2], Real(0));
  const Real sum = w[0] + w[1] + w[2];
  for (int i = 0; i < 3; ++i) w[i] /= sum;
  return true;
}

// The triangle's share of a push along unit t at weights w: sum w_i^2 / m_i.
Real triangle_inv_mass(const Model& m, const std::array<Index, 3>& tri, const Real w[3]) {
  Real sum = 0;
  for (int i = 0; i < 3; ++i) sum += w[i] * w[i] * m.inv_mass[tri[i]];
  return sum;
}

// Friction of triangle contact k at position level: undo the feature
// point's tangential motion over the substep relative to the triangle's
// point under it, with the tangential multiplier clamped to the cone
// |lambda_t| <= mu_s lambda_n. Clamped, not all-or-nothing as a particle
// contact's (solve_contact_friction): a body rests on many feature points,
// and no single point's cone can stop the whole body, so all-or-nothing
// let a box creep down an incline it should stick to (8.8 mm in 1 s at
// 20 degrees, mu 0.5). What the clamp leaves to slide, the velocity pass
// (triangle_contact_velocities) brakes with the rest of mu_d lambda_n.
void solve_triangle_friction(const Model& m, State& s, std::size_t k, const Vec3& n) {
  const BodyTriangleContact& c = s.triangle_contacts[k];
  ContactLambda& l = s.triangle_contact_lambda[k];
  if (c.static_friction <= Real(0) || l.normal <= Real(0)) return;
  RigidBody& b = body_or_world(s, c.body);
  const bool world = c.body < 0;
  const Vec3 rw = world ? Vec3::Zero() : Vec3(b.q * c.r);
  const Vec3 q = world ? c.r : Vec3(b.x + rw);
  const Vec3 q_prev = world ? c.r : Vec3(b.x_prev + b.q_prev * c.r);
  Real w[3];
  if (!triangle_weights(q, s.x[c.tri[0]], s.x[c.tri[1]], s.x[c.tri[2]], w)) return;
  Vec3 tri_moved = Vec3::Zero();
  for (int i = 0; i < 3; ++i) tri_moved += w[i] * (s.x[c.tri[i]] - s.x_prev[c.tri[i]]);
  const Vec3 rel = (q - q_prev) - tri_moved;
  const Vec3 dt = rel - n.dot(rel) * n;
  const Real len = dt.norm();
  if (!(len > kDegenerateRel * c.thickness) || len == Real(0)) return;
  const Vec3 t = dt / len;
  const Real wt = inv_mass_along(b, rw, t) + triangle_inv_mass(m, c.tri, w);
  if (!(wt > Real(0))) return;
  const Real cap = c.static_friction * l.normal;
  const Real lt = std::clamp(l.tangent - len / wt, -cap, cap);
  const Real dlt = lt - l.tangent;
  if (dlt == Real(0)) return;
  l.tangent = lt;
  for (int i = 0; i < 3; ++i) s.x[c.tri[i]] -= (m.inv_mass[c.tri[i]] * w[i] * dlt) * t;
  apply_position_impulse(b, rw, dlt * t);
  record_push(s, c.body, dlt * t);
}

}  // namespace

void solve_triangle_contacts(const Model& m, State& s, Real h) {
  for (std::size_t k = 0; k < s.triangle_contacts.size(); ++k) {
    const BodyTriangleContact& c = s.triangle_contacts[k];
    RigidBody& b = body_or_world(s, c.body);
    const Vec3 rw = c.body < 0 ? Vec3::Zero() : Vec3(b.q * c.r);
    const Vec3 q = c.body < 0 ? c.r : Vec3(b.x + rw);
    Real C;
    Vec3 g[4];
    if (!Penetration::point_triangle(q, s.x[c.tri[0]], s.x[c.tri[1]], s.x[c.tri[2]], c.side,
                                     c.thickness, C, g))
      continue;  // degenerate triangle
    Real& lambda = s.triangle_contact_lambda[k].normal;
    if (C >= Real(0) && lambda == Real(0)) continue;
    if (beyond_reach(c, C, h)) continue;
    // g[0] = s n is a unit vector: the body's share is its inverse mass along it.
    Real den = inv_mass_along(b, rw, g[0]);
    for (int i = 0; i < 3; ++i) den += m.inv_mass[c.tri[i]] * g[i + 1].squaredNorm();
    if (!(den > Real(0))) continue;
    const Real l = std::max(lambda - C / den, Real(0));
    const Real dl = l - lambda;
    lambda = l;
    for (int i = 0; i < 3; ++i) s.x[c.tri[i]] += (m.inv_mass[c.tri[i]] * dl) * g[i + 1];
    apply_position_impulse(b, rw, dl * g[0]);
    record_push(s, c.body, dl * g[0]);
    solve_triangle_friction(m, s, k, g[0]);
  }
}

void triangle_contact_velocities(const Model& m, State& s, Real h) {
  const Real inv_h = Real(1) / h;
  for (std::size_t k = 0; k < s.triangle_contacts.size(); ++k) {
    const BodyTriangleContact& c = s.triangle_contacts[k];
    const ContactLambda& l = s.triangle_contact_lambda[k];
    // What the position-level friction has not used of mu_d lambda_n.
    const Real budget = c.dynamic_friction * l.normal - std::abs(l.tangent);
    if (!(budget > Real(0))) continue;
    RigidBody& b = body_or_world(s, c.body);
    const bool world = c.body < 0;
    const Vec3 rw = world ? Vec3::Zero() : Vec3(b.q * c.r);
    const Vec3 q = world ? c.r : Vec3(b.x + rw);
    const Vec3 x1 = s.x[c.tri[0]], x2 = s.x[c.tri[1]], x3 = s.x[c.tri[2]];
    Real w[3];
    if (!triangle_weights(q, x1, x2, x3, w)) continue;
    const Vec3 nn = (x2 - x1).cross(x3 - x1);
    const Vec3 n = nn.normalized();
    Vec3 vt = (world ? Vec3::Zero() : point_velocity(b, rw));
    for (int i = 0; i < 3; ++i) vt -= w[i] * s.v[c.tri[i]];
    vt -= n.dot(vt) * n;
    const Real vt_len = vt.norm();
    if (!(vt_len > Real(0))) continue;
    const Vec3 t = vt / vt_len;
    const Real wt = inv_mass_along(b, rw, t) + triangle_inv_mass(m, c.tri, w);
    if (!(wt > Real(0))) continue;
    // At most that budget over h, and never more than stops the sliding.
    const Real jt = std::min(budget * inv_h, vt_len / wt);
    for (int i = 0; i < 3; ++i) s.v[c.tri[i]] += (m.inv_mass[c.tri[i]] * w[i] * jt) * t;
    apply_velocity_impulse(b, rw, -jt * t);
    record_impulse(s, c.body, -jt * t);
  }
}

namespace {
constexpr int kWorldContactPasses = 4;
}  // namespace

void solve_world_contacts(State& s) {
  // A body rests on several points (a box on its four corners): one pass
  // in sequence leaves it rotated by what the first points did, and a box
  // dropped flat then walks on the plane (1.7 mm/s, measured at 10 x 1).
  // The points are few and cheap, so they get kWorldContactPasses passes in
  // every sweep.
  for (int pass = 0; pass < kWorldContactPasses; ++pass) {
    for (std::size_t k = 0; k < s.world_contacts.size(); ++k) {
      const BodyWorldContact& c = s.world_contacts[k];
      ContactLambda& l = s.world_contact_lambda[k];
      RigidBody& b = s.bodies[static_cast<std::size_t>(c.body)];
      RigidBody& o = body_or_world(s, c.other);
      const Vec3 rw = b.q * c.r;
      const WorldFrame f = world_frame(s, c);
      const Real C = f.n.dot(b.x + rw - f.p) - s.world_contact_slack[k];
      if (C >= Real(0) && l.normal == Real(0)) continue;
      const Real wn = inv_mass_along(b, rw, f.n) + inv_mass_along(o, f.ro, f.n);
      if (!(wn > Real(0))) continue;
      const Real ln = std::max(l.normal - C / wn, Real(0));
      const Real dl = ln - l.normal;
      l.normal = ln;
      apply_position_impulse(b, rw, dl * f.n);
      apply_position_impulse(o, f.ro, -dl * f.n);
      // Static friction: undo the point's tangential motion over the substep
      // (relative to the other body's point) while the tangential
      // multiplier stays inside mu * lambda_n.
      if (c.friction <= Real(0) || l.normal <= Real(0)) continue;
      const Vec3 rw_now = b.q * c.r;
      Vec3 moved = (b.x + rw_now) - (b.x_prev + b.q_prev * c.r);
      Vec3 ro_now = Vec3::Zero();
      if (c.other >= 0) {
        ro_now = o.q * c.p;
        moved -= (o.x + ro_now) - (o.x_prev + o.q_prev * c.p);
      }
      const Vec3 n = c.other >= 0 ? Vec3(o.q * c.n) : c.n;
      const Vec3 dt = moved - n.dot(moved) * n;
      const Real len = dt.norm();
      if (!(len > Real(0))) continue;
      const Vec3 t = dt / len;
      const Real wt = inv_mass_along(b, rw_now, t) + inv_mass_along(o, ro_now, t);
      if (!(wt > Real(0))) continue;
      const Real dlt = -len / wt;
      if (std::abs(l.tangent + dlt) > c.friction * l.normal) continue;
      l.tangent += dlt;
      apply_position_impulse(b, rw_now, dlt * t);
      apply_position_impulse(o, ro_now, -dlt * t);
    }
  }
}

void world_contact_velocities(State& s, Real h) {
  const Real inv_h = Real(1) / h;
  for (std::size_t k = 0; k < s.world_contacts.size(); ++k) {
    const BodyWorldContact& c = s.world_contacts[k];
    const ContactLambda& l = s.world_contact_lambda[k];
    if (l.normal <= Real(0) || c.friction <= Real(0)) continue;
    RigidBody& b = s.bodies[static_cast<std::size_t>(c.body)];
    RigidBody& o = body_or_world(s, c.other);
    const Vec3 rw = b.q * c.r;
    const WorldFrame f = world_frame(s, c);
    Vec3 v = point_velocity(b, rw);
    if (c.other >= 0) v -= point_velocity(o, f.ro);
    const Vec3 vt = v - f.n.dot(v) * f.n;
    const Real vt_len = vt.norm();
    if (!(vt_len > Real(0))) continue;
    const Vec3 t = vt / vt_len;
    const Real wt = inv_mass_along(b, rw, t) + inv_mass_along(o, f.ro, t);
    if (!(wt > Real(0))) continue;
    // Dynamic Coulomb friction: at most mu (lambda_n / h) and never
    // reversing the sliding.
    const Real jt = std::min(c.friction * l.normal * inv_h, vt_len / wt);
    apply_velocity_impulse(b, rw, -jt * t);
    apply_velocity_impulse(o, f.ro, jt * t);
  }
}

namespace {
// Calls f(C, thickness) for every body contact and rigid-feature-vs-triangle
// contact of the state within its reach in a substep of h, C the contact
// constraint at the current positions.
template <class F>
void for_each_contact_constraint(const State& s, Real h, F&& f) {
  for (const BodyContact& c : s.contacts) {
    const RigidBody& b = body_or_world(s, c.body);
    const Frame fr = contact_frame(b, c, c.body < 0, s.x[c.particle]);
    f(fr.n.dot(s.x[c.particle] - fr.p) - c.thickness, c.thickness);
  }
  for (const BodyTriangleContact& c : s.triangle_contacts) {
    const RigidBody& b = body_or_world(s, c.body);
    const Vec3 q = c.body < 0 ? c.r : Vec3(b.x + b.q * c.r);
    Real C;
    Vec3 g[4];
    if (Penetration::point_triangle(q, s.x[c.tri[0]], s.x[c.tri[1]], s.x[c.tri[2]], c.side, c.thickness, C, g) &&
        !beyond_reach(c, C, h))
      f(C, c.thickness);
  }
  for (std::size_t k = 0; k < s.edge_contacts.size(); ++k) {
    Real C, t;
    Vec3 n, rw;
    if (edge_contact_constraint(s, k, h, C, n, t, rw)) f(C, s.edge_contacts[k].thickness);
  }
}
}  // namespace

Real worst_contact_violation(const Model& m, const State& s, Real h) {
  (void)m;
  Real worst = 0;
  for_each_contact_constraint(s, h, [&](Real C, Real thickness) {
    if (C < Real(0) && thickness > Real(0)) worst = std::max(worst, -C / thickness);
  });
  return worst;
}

Real deepest_contact_violation(const State& s, Real h) {
  Real deepest = 0;
  for_each_contact_constraint(s, h, [&](Real C, Real) {
    if (C < Real(0)) deepest = std::max(deepest, -C);
  });
  return deepest;
}

void update_body_velocities(std::vector<RigidBody>& bodies, Real h, Real blend) {
  const Real inv_h = Real(1) / h;
  for (RigidBody& b : bodies) {
    const Vec3 v_pred = b.v, w_pred = b.w;
    b.v = (b.x - b.x_prev) * inv_h;
    Quat dq = b.q * b.q_prev.conjugate();
    if (dq.w() < Real(0)) dq.coeffs() = -dq.coeffs();
    // The inverse of predict_bodies' step q' = normalize(q + h/2 [w, 0] q),
    // whose rotation is dq = (1, h w / 2) normalized: w = (2/h) vec(dq) / dq.w.
    // Read back without the division, (2/h) vec(dq), a free spin lost a
    // factor sqrt(1 + (h w / 2)^2) of its rate in every substep: a bar
    // spinning at 50 rad/s at 600 Hz kept 57 % of it after 2 s (32 % of its
    // energy; tests/unit/test_rigid_gyroscopic.cpp without the term).
    // A turn of more than 120 degrees in one substep, which that step does
    // not resolve, is read back with dq.w taken as 1/2: bounded.
    b.w = (Real(2) * inv_h / std::max(dq.w(), Real(0.5))) * dq.vec();
    if (blend < Real(1) && b.inv_mass > Real(0)) {
      b.v = v_pred + blend * (b.v - v_pred);
      b.w = w_pred + blend * (b.w - w_pred);
    }
  }
}

void contact_velocities(const Model& m, State& s, Real h, Real gravity_norm) {
  const Real inv_h = Real(1) / h;
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    const BodyContact& c = s.contacts[k];
    const ContactLambda& l = s.contact_lambda[k];
    if (l.normal <= Real(0)) continue;  // not touching in this substep
    RigidBody& b = body_or_world(s, c.body);
    const bool world = c.body < 0;
    const Index p = c.particle;
    const Real wp = m.inv_mass[p];
    const Frame f = contact_frame(b, c, world, s.x[p]);
    const auto rel_velocity = [&] {
      return Vec3(s.v[p] - (world ? Vec3::Zero() : point_velocity(b, f.rw)));
    };
    Vec3 vr = rel_velocity();
    const Real vn = f.n.dot(vr);
    const Vec3 vt = vr - vn * f.n;
    const Real vt_len = vt.norm();

    // Dynamic Coulomb friction: the tangential impulse is at most
    // mu_d * (normal impulse lambda_n / h) and never reverses the sliding.
    if (c.dynamic_friction > Real(0) && vt_len > Real(0) && !l.joint) {
      const Vec3 t = vt / vt_len;
      const Real wt = wp + inv_mass_along(b, f.rw, t);
      if (wt > Real(0)) {
        const Real jt = std::min(c.dynamic_friction * l.normal * inv_h, vt_len / wt);
        s.v[p] -= (wp * jt) * t;
        apply_velocity_impulse(b, f.rw, jt * t);
        record_impulse(s, c.body, jt * t);
      }
    }

    // Restitution: if the approach at the substep start was faster than what
    // gravity adds in two substeps (resting contact), reflect it.
    if (c.restitution > Real(0) && l.vn_start < -Real(2) * gravity_norm * h) {
      vr = rel_velocity();
      const Real target = -c.restitution * l.vn_start;
      const Real wn = wp + inv_mass_along(b, f.rw, f.n);
      if (wn > Real(0)) {
        const Real jn = (target - f.n.dot(vr)) / wn;
        s.v[p] += (wp * jn) * f.n;
        apply_velocity_impulse(b, f.rw, -jn * f.n);
        record_impulse(s, c.body, -jn * f.n);
      }
    }
  }
}

}  // namespace xpbd::rigid
