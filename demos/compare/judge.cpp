// How a run is judged against its reference (compare.hpp): the error of a
// sample with the rigid bodies in it, the side of the cloth a body is on,
// a body that has left the scene, and the mean or worst over the samples.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "demos/compare/compare.hpp"

namespace xpbd_compare {

double SampleError::judged() const {
  if (std::isnan(rms) || std::isnan(body)) return std::nan("");
  return std::max(rms, body);
}

SampleError sample_error(const Sample& run, const Sample& ref) {
  const PositionError p = position_error(run.x, ref.x);
  const PositionError b = position_error(run.bodies, ref.bodies);
  SampleError e;
  e.rms = p.rms;
  e.max = p.max;
  e.body = b.max;
  if (std::isnan(p.rms) || std::isnan(b.max)) e.rms = e.max = e.body = std::nan("");
  return e;
}

namespace {

// Ericson, Real-Time Collision Detection, 5.1.5: the point of triangle abc
// nearest to p, as barycentric weights (u, v, w) of (a, b, c).
std::array<double, 3> nearest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const double denom = 1 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return {1 - v - w, v, w};
}

}  // namespace

int side_of_surface(const Vec3& p, std::span<const Vec3> x, std::span<const std::array<xpbd::Index, 3>> triangles,
                     double margin) {
  using V = Eigen::Vector3d;
  const V q = p.template cast<double>();
  auto at = [&](xpbd::Index i) -> V {
    if (i < 0 || std::size_t(i) >= x.size())
      throw std::out_of_range("side_of_surface: triangle index " + std::to_string(i) + " outside " +
                              std::to_string(x.size()) + " positions");
    return x[std::size_t(i)].template cast<double>();
  };
  // The nearest feature: a triangle's interior, one of its edges or corners.
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_t = 0;
  std::array<double, 3> best_w{};
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const V a = at(triangles[t][0]), b = at(triangles[t][1]), c = at(triangles[t][2]);
    const auto w = nearest_on_triangle(q, a, b, c);
    const double d = (q - (w[0] * a + w[1] * b + w[2] * c)).norm();
    if (d < best) {
      best = d;
      best_t = t;
      best_w = w;
    }
  }
  if (!(best > margin) || !std::isfinite(best)) return 0;
  const auto& tri = triangles[best_t];
  const V near = best_w[0] * at(tri[0]) + best_w[1] * at(tri[1]) + best_w[2] * at(tri[2]);
  // The normal of the nearest feature (Baerentzen and Aanaes' pseudo-normal):
  // a face's own; an edge's, the sum of its faces' unit normals; a corner's,
  // the sum of its faces' unit normals weighted by their angle there. On the
  // border (an edge with one face, a corner on such an edge) the side is not
  // defined: no verdict.
  std::vector<int> on;  // the triangle's corners the nearest point lies on
  for (int k = 0; k < 3; ++k)
    if (best_w[k] > 1e-9) on.push_back(k);
  V n = V::Zero();
  if (on.size() == 3) {
    n = (at(tri[1]) - at(tri[0])).cross(at(tri[2]) - at(tri[0]));
  } else {
    std::vector<xpbd::Index> feature;
    for (int k : on) feature.push_back(tri[k]);
    int faces = 0;
    std::map<std::pair<xpbd::Index, xpbd::Index>, int> edge_faces;  // corners only: is it on the border?
    for (const auto& t : triangles) {
      for (int k = 0; k < 3; ++k) {
        const xpbd::Index i = t[k], j = t[(k + 1) % 3];
        if (feature.size() == 1 && (i == feature[0] || j == feature[0])) ++edge_faces[std::minmax(i, j)];
      }
      const bool has = std::all_of(feature.begin(), feature.end(),
                                   [&](xpbd::Index f) { return f == t[0] || f == t[1] || f == t[2]; });
      if (!has) continue;
      ++faces;
      const V a = at(t[0]), b = at(t[1]), c = at(t[2]);
      V fn = (b - a).cross(c - a);
      if (fn.norm() == 0) continue;
      fn.normalize();
      double weight = 1;
      if (feature.size() == 1) {
        // The angle of this face at the corner.
        const int k = t[0] == feature[0] ? 0 : t[1] == feature[0] ? 1 : 2;
        const V e1 = at(t[(k + 1) % 3]) - at(t[k]), e2 = at(t[(k + 2) % 3]) - at(t[k]);
        weight = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      }
      n += weight * fn;
    }
    const bool border = feature.size() == 2 ? faces < 2
                                            : std::any_of(edge_faces.begin(), edge_faces.end(),
                                                          [](const auto& e) { return e.second < 2; });
    if (border) return 0;
  }
  if (!(n.norm() > 0)) return 0;
  return n.dot(q - near) > 0 ? 1 : -1;
}

std::optional<int> wrong_side_frame(const Snapshots& run, const Snapshots& ref,
                                    std::span<const std::array<xpbd::Index, 3>> triangles, double margin) {
  for (const auto& [f, a] : run) {
    const auto b = ref.find(f);
    if (b == ref.end() || a.bodies.size() != b->second.bodies.size()) continue;
    for (std::size_t k = 0; k < a.bodies.size(); ++k) {
      const int sa = side_of_surface(a.bodies[k], a.x, triangles, margin);
      const int sb = side_of_surface(b->second.bodies[k], b->second.x, triangles, margin);
      if (sa != 0 && sb != 0 && sa != sb) return f;
    }
  }
  return std::nullopt;
}

std::optional<int> lost_body_frame(const Snapshots& run, const Snapshots& ref) {
  for (const auto& [f, a] : run) {
    const auto b = ref.find(f);
    if (b == ref.end() || b->second.x.empty() || a.bodies.size() != b->second.bodies.size()) continue;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Vec3& p : b->second.x) {
      lo = lo.cwiseMin(p.template cast<double>());
      hi = hi.cwiseMax(p.template cast<double>());
    }
    const double size = (hi - lo).norm();
    for (std::size_t k = 0; k < a.bodies.size(); ++k) {
      const double d = (a.bodies[k].template cast<double>() - b->second.bodies[k].template cast<double>()).norm();
      if (!(d <= size)) return f;
    }
  }
  return std::nullopt;
}

std::optional<SampleError> error_at(const Row& r, double t) {
  std::istringstream in(r.err_series);
  std::string item;
  while (std::getline(in, item, ';')) {
    std::istringstream f(item);
    std::string field;
    std::vector<double> v;
    try {
      while (std::getline(f, field, ':')) v.push_back(std::stod(field));  // "inf" and "nan" parse
    } catch (const std::exception&) {
      continue;  // not a series entry
    }
    if (v.size() == 4 && std::abs(v[0] - t) <= 1e-6) return SampleError{v[1], v[2], v[3]};
  }
  return std::nullopt;
}

double judged_error(const Row& r, Judge j) {
  if (static_reference(r.scene)) return r.err_rms_final;
  return j == Judge::mean ? r.err_mean : r.err_worst;
}

const char* judge_name(Judge j) { return j == Judge::mean ? "mean" : "worst"; }

Judge parse_judge(const std::string& s) {
  if (s == "mean") return Judge::mean;
  if (s == "worst") return Judge::worst;
  throw std::invalid_argument("judge: expected mean or worst, got \"" + s + "\"");
}

}  // namespace xpbd_compare
