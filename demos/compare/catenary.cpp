#include "demos/compare/catenary.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

namespace xpbd_compare {

namespace {

using V3d = Eigen::Vector3d;

std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

[[noreturn]] void bad(const std::string& field, const std::string& what) {
  throw std::invalid_argument("CatenaryParams." + field + ": " + what);
}

void check_finite(const char* field, double v) {
  if (!std::isfinite(v)) bad(field, "must be finite, got " + num(v));
}

void check_finite(const char* field, const Vec3& v) {
  if (!v.allFinite())
    bad(field, "must be finite, got (" + num(double(v.x())) + ", " + num(double(v.y())) + ", " +
                   num(double(v.z())) + ")");
}

// The plane of the problem: a at the origin, e the horizontal unit vector
// from a towards b, y up. D = horizontal span (m, > 0), h = b_y - a_y (m).
struct Plane {
  V3d a, e;
  double D = 0, h = 0;
};

Plane plane_of(const CatenaryParams& p) {
  Plane pl;
  pl.a = p.a.cast<double>();
  const V3d d = p.b.cast<double>() - pl.a;
  V3d horiz(d.x(), 0, d.z());
  pl.D = horiz.norm();
  pl.e = horiz / pl.D;
  pl.h = d.y();
  return pl;
}

// The chain for given (H, V0), see the header: link k from particle k to
// k+1 has vertical tension V_k = V0 - k m g (positive: the link runs
// downhill from k to k+1), tension T_k = |(H, V_k)|, length l + alpha T_k
// and in-plane direction (H, -V_k) / T_k. end = sum of the links
// (horizontal, vertical) in the plane; J = d end / d(H, V0).
struct Shape {
  double end_x = 0, end_y = 0;
  Eigen::Matrix2d J;
};

Shape shape(const CatenaryParams& p, double H, double V0) {
  const double l = p.spacing, alpha = p.compliance, w = double(p.mass) * double(p.g);
  Shape s;
  s.J.setZero();
  for (int k = 0; k + 1 < p.n; ++k) {
    const double V = V0 - k * w;
    const double T = std::hypot(H, V);
    // Link k: horizontal l H/T + alpha H, vertical -(l V/T + alpha V).
    s.end_x += l * H / T + alpha * H;
    s.end_y -= l * V / T + alpha * V;
    // d(H/T)/dH = V^2/T^3, d(H/T)/dV = d(V/T)/dH = -H V/T^3,
    // d(V/T)/dV = H^2/T^3; dV/dV0 = 1.
    const double T3 = T * T * T;
    s.J(0, 0) += l * V * V / T3 + alpha;
    s.J(0, 1) += -l * H * V / T3;
    s.J(1, 0) += l * H * V / T3;
    s.J(1, 1) += -(l * H * H / T3 + alpha);
  }
  return s;
}

// Initial guess from the continuous inextensible catenary of the same length
// L and weight per length w = m g / l through the same two points: with
// u = D / (2c), sinh(u)/u = sqrt(L^2 - h^2) / D; H = w c; the lowest point
// is at x_low = D/2 - c asinh(h / (2 c sinh u)) from a, so the slope at a is
// -sinh(x_low / c) and V0 = H sinh(x_low / c).
std::array<double, 2> initial_guess(const CatenaryParams& p, const Plane& pl) {
  const double L = (p.n - 1) * double(p.spacing);
  const double r = std::sqrt(L * L - pl.h * pl.h) / pl.D;  // > 1 (checked)
  auto f = [](double u) { return std::sinh(u) / u; };
  double lo = 0, hi = 1;
  while (f(hi) < r && hi < 700) hi *= 2;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (mid > 0 && f(mid) < r ? lo : hi) = mid;
  }
  const double u = std::max(0.5 * (lo + hi), 1e-12);
  const double c = pl.D / (2 * u);
  const double H = double(p.mass) * double(p.g) / double(p.spacing) * c;
  const double x_low = pl.D / 2 - c * std::asinh(pl.h / (2 * c * std::sinh(u)));
  return {H, H * std::sinh(x_low / c)};
}

}  // namespace

void check_catenary_params(const CatenaryParams& p) {
  check_finite("mass", p.mass);
  check_finite("spacing", p.spacing);
  check_finite("g", p.g);
  check_finite("compliance", p.compliance);
  check_finite("drag", p.drag);
  check_finite("start_angle", p.start_angle);
  check_finite("a", p.a);
  check_finite("b", p.b);
  if (p.n < 3) bad("n", "need at least 3 particles (one free between the supports), got " + std::to_string(p.n));
  if (!(p.mass > 0)) bad("mass", "must be > 0 kg, got " + num(p.mass));
  if (!(p.spacing > 0)) bad("spacing", "must be > 0 m, got " + num(p.spacing));
  if (!(p.g > 0)) bad("g", "must be > 0 m/s^2 (gravity along -y), got " + num(p.g));
  if (!(p.compliance >= 0)) bad("compliance", "must be >= 0 m/N, got " + num(p.compliance));
  if (!(p.drag >= 0)) bad("drag", "must be >= 0 1/s, got " + num(p.drag));
  const V3d d = p.b.cast<double>() - p.a.cast<double>();
  if (std::hypot(d.x(), d.z()) == 0)
    bad("b", "must differ from a horizontally (x or z): a = (" + num(p.a.x()) + ", " + num(p.a.y()) + ", " +
                 num(p.a.z()) + "), b = (" + num(p.b.x()) + ", " + num(p.b.y()) + ", " + num(p.b.z()) +
                 "); a chain hanging from one point is chain_equilibrium's vertical chain");
  const double L = (p.n - 1) * double(p.spacing);
  if (!(d.norm() < L))
    bad("b", "the supports are " + num(d.norm()) + " m apart, not less than the chain's rest length (n-1) spacing = " +
                 num(L) + " m: the chain cannot reach without stretching");
}

CatenaryEquilibrium catenary_equilibrium(const CatenaryParams& p) {
  check_catenary_params(p);
  const Plane pl = plane_of(p);
  const double L = (p.n - 1) * double(p.spacing);
  auto residual = [&](double H, double V0, Shape* out) {
    const Shape s = shape(p, H, V0);
    if (out) *out = s;
    return std::hypot(s.end_x - pl.D, s.end_y - pl.h);
  };

  // Not a structured binding: the lambda below reads H and V0, and clang 14
  // (the sanitizer build) cannot capture structured bindings.
  const auto guess = initial_guess(p, pl);
  double H = guess[0], V0 = guess[1];
  Shape s;
  double res = residual(H, V0, &s);
  // Scale of the round-off: the summed link lengths (the stretched length,
  // which a very compliant chain makes far longer than L). Stop at a few eps
  // of it; converged below 1e-12 of it.
  auto length_scale = [&] {
    return std::max(L, L + double(p.compliance) * (p.n - 1) * std::hypot(H, std::abs(V0) + p.n * double(p.mass) * double(p.g)));
  };
  int it = 0;
  for (; it < 100 && res > 8 * std::numeric_limits<double>::epsilon() * length_scale(); ++it) {
    const Eigen::Vector2d F(s.end_x - pl.D, s.end_y - pl.h);
    // J is never singular: det J = b^2 - (A + alpha (n-1)) (C + alpha (n-1))
    // with A = sum l V^2/T^3, C = sum l H^2/T^3, b = sum l H V/T^3, and
    // b^2 < A C by Cauchy-Schwarz since the V_k/H are not all equal.
    const Eigen::Vector2d step = -s.J.partialPivLu().solve(F);
    // Damped: halve the step until H stays > 0 and the residual drops.
    double t = 1;
    while (H + t * step(0) <= 0) t /= 2;
    bool improved = false;
    for (int k = 0; k < 60; ++k, t /= 2) {
      Shape s2;
      const double r2 = residual(H + t * step(0), V0 + t * step(1), &s2);
      if (r2 < res) {
        H += t * step(0);
        V0 += t * step(1);
        res = r2;
        s = s2;
        improved = true;
        break;
      }
    }
    if (!improved) break;  // at round-off
  }
  const double converged = 1e-12 * length_scale();
  if (!(res <= converged)) {
    std::string msg = "catenary_equilibrium: Newton's method did not converge after " + std::to_string(it) +
                      " iterations: the chain ends " + num(res) + " m from support b (need <= " + num(converged) +
                      " m); H = " + num(H) + " N, V0 = " + num(V0) + " N";
    // H -> 0: every link but the one at the fold tends to vertical. With the
    // supports almost above each other and a whole number of links apart
    // vertically this is degenerate (seen: 1e-5 m horizontally, 18 links
    // vertically): Newton drives H to 0 and the ends never meet.
    if (H < 1e-6 * double(p.mass) * double(p.g))
      msg += "; the supports are nearly above each other (horizontal span " + num(pl.D) + " m, vertical " +
             num(pl.h) + " m, link " + num(p.spacing) + " m): the folded chain is degenerate (found no equilibrium with every link in tension)";
    throw std::runtime_error(msg);
  }

  CatenaryEquilibrium eq;
  eq.H = H;
  eq.V0 = V0;
  eq.newton_iterations = it;
  const double w = double(p.mass) * double(p.g);
  const double Vlast = V0 - (p.n - 2) * w;
  eq.support_force_a = std::hypot(H, V0);
  eq.support_force_b = std::hypot(H, Vlast);
  eq.support_vertical_a = V0;
  eq.support_vertical_b = -Vlast;
  const V3d up(0, 1, 0);
  V3d x = pl.a;
  eq.x.reserve(std::size_t(p.n));
  eq.x.push_back(x.cast<Real>());
  for (int k = 0; k + 1 < p.n; ++k) {
    const double V = V0 - k * w;
    const double T = std::hypot(H, V);
    const double len = double(p.spacing) + double(p.compliance) * T;
    x += len / T * (H * pl.e - V * up);
    eq.x.push_back(x.cast<Real>());
  }
  eq.residual = (x - p.b.cast<double>()).norm();
  return eq;
}

xpbd_demos::SceneSpec catenary_scene(const CatenaryParams& p, int frames) {
  check_catenary_params(p);
  if (frames < 1) throw std::invalid_argument("catenary_scene: frames must be >= 1, got " + std::to_string(frames));
  // Start: the inextensible equilibrium (every link exactly `spacing` long
  // up to round-off, ends at a and b), turned about the support line by
  // start_angle (Rodrigues' formula; a rigid rotation keeps the lengths).
  CatenaryParams rigid = p;
  rigid.compliance = 0;
  const CatenaryEquilibrium start = catenary_equilibrium(rigid);
  const V3d a = p.a.cast<double>(), b = p.b.cast<double>();
  const V3d k = (b - a).normalized();
  const double c = std::cos(double(p.start_angle)), sn = std::sin(double(p.start_angle));

  xpbd_demos::SceneSpec s;
  s.name = "catenary";
  std::ostringstream d;
  d << "chain of " << p.n << " particles of " << p.mass << " kg, " << p.spacing << " m links (compliance "
    << p.compliance << " m/N) hanging between two pinned supports " << (b - a).norm()
    << " m apart; starts at rest as the inextensible catenary";
  if (p.start_angle != 0) d << " turned " << p.start_angle << " rad about the support line";
  s.description = d.str();
  xpbd::SceneDesc& sc = s.soft.particles;
  for (int i = 0; i < p.n; ++i) {
    V3d x;
    if (i == 0) {
      x = a;
    } else if (i == p.n - 1) {
      x = b;  // the solution ends within ~1e-15 m of b
    } else {
      const V3d v = start.x[std::size_t(i)].cast<double>() - a;
      x = a + v * c + k.cross(v) * sn + k * k.dot(v) * (1 - c);
    }
    const bool end = i == 0 || i == p.n - 1;
    // End particles: mass 0 (kinematic), pinned where they start.
    const xpbd::Index idx = sc.add_particle(x.cast<Real>(), end ? Real(0) : p.mass);
    if (end) sc.pins.push_back(xpbd::PinDesc{idx, std::nullopt, xpbd::Material{}});
    if (i > 0) {
      xpbd::Material m;
      m.compliance = p.compliance;
      sc.distances.push_back(xpbd::DistanceDesc{idx - 1, idx, p.spacing, m});
    }
  }
  s.solver.gravity = Vec3(0, -p.g, 0);
  s.solver.drag = p.drag;
  s.solver.frames = frames;
  return s;
}

}  // namespace xpbd_compare
