// Rigid edges against soft edges (xpbd::BodyEdgeContact, rigid.hpp): the
// constraint between the two lines' closest points and its projection.
#include <cmath>

#include "rigid_internal.hpp"
#include "xpbd/rigid_solve.hpp"

namespace xpbd::rigid {

using namespace detail;

namespace {
// Edges closer to parallel than this (sine of the angle between them) have
// no normal: the feature points along the rigid edge answer there.
constexpr Real kParallelSin = Real(0.02);
}  // namespace

bool edge_contact_constraint(const State& s, std::size_t k, Real h, Real& C, Vec3& n, Real& t, Vec3& rw) {
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
  return true;
}

void solve_edge_contacts(const Model& m, State& s, Real h) {
  for (std::size_t k = 0; k < s.edge_contacts.size(); ++k) {
    const BodyEdgeContact& c = s.edge_contacts[k];
    Real C, t;
    Vec3 n, rw;
    if (!edge_contact_constraint(s, k, h, C, n, t, rw)) continue;
    Real& lambda = s.edge_contact_lambda[k];
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
  }
}

}  // namespace xpbd::rigid
