// Rigid edges against soft edges (xpbd::BodyEdgeContact, rigid.hpp): the
// constraint between the two lines' closest points and its projection.
#include <algorithm>
#include <cmath>

#include "rigid_internal.hpp"
#include "xpbd/rigid_solve.hpp"

namespace xpbd::rigid {

using namespace detail;

namespace {
// Edges closer to parallel than this (sine of the angle between them) have
// no normal: the contacts of the soft edge's two particles answer there
// (with both ends the thickness away, a soft edge of length L this close
// to parallel stays at least thickness - 0.02 L from the rigid edge's
// line).
constexpr Real kParallelSin = Real(0.02);
}  // namespace

bool edge_contact_constraint(const State& s, std::size_t k, Real h, Real& C, Vec3& n, Real& t, Vec3& rw, Real* u_out) {
  const BodyEdgeContact& c = s.edge_contacts[k];
  const RigidBody& b = body_or_world(s, c.body);
  const bool world = c.body < 0;
  const Vec3 ra = world ? c.a : Vec3(b.q * c.a), rb = world ? c.b : Vec3(b.q * c.b);
  const Vec3 A = world ? c.a : Vec3(b.x + ra);
  const Vec3 er = rb - ra;
  const Vec3 P = s.x[c.p[0]], es = s.x[c.p[1]] - P;
  const Vec3 nn = er.cross(es);
  const Real rr = er.squaredNorm(), ss = es.squaredNorm(), n2 = nn.squaredNorm();
  if (!(n2 > kParallelSin * kParallelSin * rr * ss)) return false;
  // Closest points of the lines A + u er and P + t es.
  const Vec3 w0 = A - P;
  const Real rs = er.dot(es), d = er.dot(w0), e = es.dot(w0);
  const Real u = (rs * e - ss * d) / n2;  // n2 = rr ss - rs^2
  t = (rr * e - rs * d) / n2;
  if (!(u >= Real(0) && u <= Real(1) && t >= Real(0) && t <= Real(1))) return false;
  n = nn / std::sqrt(n2);
  const Real lean = n.dot(world ? c.out : Vec3(b.q * c.out));
  if (!(std::abs(lean) >= kEdgeLean)) return false;
  if (lean < Real(0)) n = -n;
  C = n.dot(P - A) - c.thickness;  // n is normal to both edges
  if (-(C + c.thickness) > c.reach + c.closing_speed * h) return false;
  rw = world ? Vec3::Zero() : Vec3(ra + u * er);
  if (u_out != nullptr) *u_out = u;
  return true;
}

namespace {

// The soft edge's inverse mass at its point x_s(t) along a unit direction.
Real soft_edge_inv_mass(const Model& m, const BodyEdgeContact& c, Real t) {
  return m.inv_mass[c.p[0]] * (Real(1) - t) * (Real(1) - t) + m.inv_mass[c.p[1]] * t * t;
}

// Static Coulomb friction of edge contact k after its push (as a triangle
// contact's, solve_triangle_friction): the body's point x_r(u) and the soft
// edge's point x_s(t) moved apart along the contact over the substep; undo
// that within mu_s lambda_n, the rest is left to edge_contact_velocities.
void solve_edge_friction(const Model& m, State& s, std::size_t k, const Vec3& n, Real t, Real u) {
  const BodyEdgeContact& c = s.edge_contacts[k];
  ContactLambda& l = s.edge_contact_lambda[k];
  if (c.static_friction <= Real(0) || l.normal <= Real(0)) return;
  RigidBody& b = body_or_world(s, c.body);
  const bool world = c.body < 0;
  const Vec3 local = c.a + u * (c.b - c.a);
  const Vec3 rw = world ? Vec3::Zero() : Vec3(b.q * local);
  const Vec3 q = world ? local : Vec3(b.x + rw);
  const Vec3 q_prev = world ? local : Vec3(b.x_prev + b.q_prev * local);
  const Vec3 soft_moved = (Real(1) - t) * (s.x[c.p[0]] - s.x_prev[c.p[0]]) + t * (s.x[c.p[1]] - s.x_prev[c.p[1]]);
  const Vec3 rel = (q - q_prev) - soft_moved;
  const Vec3 dt = rel - n.dot(rel) * n;
  const Real len = dt.norm();
  if (!(len > kDegenerateRel * c.thickness) || len == Real(0)) return;
  const Vec3 dir = dt / len;
  const Real wt = inv_mass_along(b, rw, dir) + soft_edge_inv_mass(m, c, t);
  if (!(wt > Real(0))) return;
  const Real cap = c.static_friction * l.normal;
  const Real lt = std::clamp(l.tangent - len / wt, -cap, cap);
  const Real dlt = lt - l.tangent;
  if (dlt == Real(0)) return;
  l.tangent = lt;
  s.x[c.p[0]] -= (m.inv_mass[c.p[0]] * (Real(1) - t) * dlt) * dir;
  s.x[c.p[1]] -= (m.inv_mass[c.p[1]] * t * dlt) * dir;
  apply_position_impulse(b, rw, dlt * dir);
  record_push(s, c.body, dlt * dir);
}

}  // namespace

void solve_edge_contacts(const Model& m, State& s, Real h) {
  const Real inv_h2 = Real(1) / (h * h);
  for (std::size_t k = 0; k < s.edge_contacts.size(); ++k) {
    const BodyEdgeContact& c = s.edge_contacts[k];
    Real C, t, u;
    Vec3 n, rw;
    if (!edge_contact_constraint(s, k, h, C, n, t, rw, &u)) continue;
    Real& lambda = s.edge_contact_lambda[k].normal;
    if (C >= Real(0) && lambda == Real(0)) continue;
    RigidBody& b = body_or_world(s, c.body);
    const Real w0 = m.inv_mass[c.p[0]] * (Real(1) - t), w1 = m.inv_mass[c.p[1]] * t;
    const Real den = inv_mass_along(b, rw, n) + w0 * (Real(1) - t) + w1 * t;
    if (!(den > Real(0))) continue;
    const Real l = std::max(lambda - C / den, Real(0));
    const Real dl = l - lambda;
    lambda = l;
    s.x[c.p[0]] += (w0 * dl) * n;
    s.x[c.p[1]] += (w1 * dl) * n;
    apply_position_impulse(b, rw, -dl * n);
    record_push(s, c.body, -dl * n);
    solve_edge_friction(m, s, k, n, t, u);
    // The push moved the two particles along n, which leans off the normals
    // of their own contacts (a cloth lying on the ground under a box's edge
    // that comes down at a slant): they slid along those contacts. Their
    // friction, solved earlier in the sweep, takes that back now; left to
    // the next sweep, the last sweep's slide stays, and the box's edge
    // pushed the cloth out from under it (docs/squeeze.md).
    for (const Index head : s.edge_contact_head[k])
      if (head >= 0) solve_particle_friction(m, s, static_cast<std::size_t>(head), inv_h2);
  }
}

void edge_contact_velocities(const Model& m, State& s, Real h) {
  const Real inv_h = Real(1) / h;
  for (std::size_t k = 0; k < s.edge_contacts.size(); ++k) {
    const BodyEdgeContact& c = s.edge_contacts[k];
    const ContactLambda& l = s.edge_contact_lambda[k];
    // What the position-level friction has not used of mu_d lambda_n.
    const Real budget = c.dynamic_friction * l.normal - std::abs(l.tangent);
    if (!(budget > Real(0))) continue;
    Real C, t;
    Vec3 n, rw;
    if (!edge_contact_constraint(s, k, h, C, n, t, rw)) continue;
    RigidBody& b = body_or_world(s, c.body);
    Vec3 vt = (c.body < 0 ? Vec3::Zero() : point_velocity(b, rw)) -
              ((Real(1) - t) * s.v[c.p[0]] + t * s.v[c.p[1]]);
    vt -= n.dot(vt) * n;
    const Real vt_len = vt.norm();
    if (!(vt_len > Real(0))) continue;
    const Vec3 dir = vt / vt_len;
    const Real wt = inv_mass_along(b, rw, dir) + soft_edge_inv_mass(m, c, t);
    if (!(wt > Real(0))) continue;
    // At most that budget over h, and never more than stops the sliding.
    const Real jt = std::min(budget * inv_h, vt_len / wt);
    s.v[c.p[0]] += (m.inv_mass[c.p[0]] * (Real(1) - t) * jt) * dir;
    s.v[c.p[1]] += (m.inv_mass[c.p[1]] * t * jt) * dir;
    apply_velocity_impulse(b, rw, -jt * dir);
    record_impulse(s, c.body, -jt * dir);
  }
}

}  // namespace xpbd::rigid
