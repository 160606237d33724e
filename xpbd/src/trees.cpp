// Direct solve over trees of Distance elements (trees.hpp,
// StepConfig::direct_chains).
#include "xpbd/trees.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "chains_solve.hpp"
#include "trees_solve.hpp"
#include "xpbd/constraints.hpp"
#include "xpbd/model.hpp"
#include "xpbd/state.hpp"

namespace xpbd {

Trees find_trees(const std::vector<Distance>& elements, const std::vector<Real>& inv_mass) {
  Trees out;
  out.num_distance = elements.size();
  out.num_particles = inv_mass.size();
  const std::size_t np = inv_mass.size(), ne = elements.size();
  auto moving = [&](Index p) { return p >= 0 && static_cast<std::size_t>(p) < np && inv_mass[std::size_t(p)] > Real(0); };
  auto eligible = [&](std::size_t k) {
    const Distance& e = elements[k];
    return e.mat.damping == Real(0) && e.p[0] != e.p[1] && (moving(e.p[0]) || moving(e.p[1]));
  };
  // Eligible elements per moving particle (CSR).
  std::vector<Index> first(np + 1, 0), adj;
  for (std::size_t k = 0; k < ne; ++k)
    if (eligible(k))
      for (Index p : elements[k].p)
        if (moving(p)) ++first[std::size_t(p) + 1];
  for (std::size_t i = 0; i < np; ++i) first[i + 1] += first[i];
  adj.resize(std::size_t(first[np]));
  {
    std::vector<Index> cursor(first.begin(), first.end() - 1);
    for (std::size_t k = 0; k < ne; ++k)
      if (eligible(k))
        for (Index p : elements[k].p)
          if (moving(p)) adj[std::size_t(cursor[std::size_t(p)]++)] = Index(k);
  }
  // Each connected set, breadth first from its lowest moving particle: the
  // nodes in the order found (a node's parent before it), each with its
  // parent. A set with a loop reaches some node a second time.
  struct Found {
    Index index;
    bool element;
    Index parent;  // position in `order`
  };
  std::vector<char> seen_particle(np, 0), seen_element(ne, 0);
  std::vector<Found> order;
  for (std::size_t start = 0; start < np; ++start) {
    if (seen_particle[start] || first[start] == first[start + 1]) continue;
    order.clear();
    order.push_back({Index(start), false, -1});
    seen_particle[start] = 1;
    bool loop = false, branched = false;
    for (std::size_t q = 0; q < order.size(); ++q) {
      const Found f = order[q];
      if (!f.element) {
        const auto p = std::size_t(f.index);
        if (first[p + 1] - first[p] >= 3) branched = true;
        for (Index a = first[p]; a < first[p + 1]; ++a) {
          const auto k = std::size_t(adj[std::size_t(a)]);
          if (f.parent >= 0 && order[std::size_t(f.parent)].element && std::size_t(order[std::size_t(f.parent)].index) == k)
            continue;  // the element it was reached by
          if (seen_element[k]) {
            loop = true;
            continue;
          }
          seen_element[k] = 1;
          order.push_back({Index(k), true, Index(q)});
        }
      } else {
        const Distance& e = elements[std::size_t(f.index)];
        const Index from = order[std::size_t(f.parent)].index;
        for (Index p : e.p) {
          if (!moving(p) || p == from) continue;
          if (seen_particle[std::size_t(p)]) {
            loop = true;
            continue;
          }
          seen_particle[std::size_t(p)] = 1;
          order.push_back({p, false, Index(q)});
        }
      }
    }
    // A path is a chain's (chains.hpp); a set with a loop is no tree.
    if (loop || !branched) continue;
    // Stored leaves first: the reverse of the order found.
    const auto base = static_cast<Index>(out.index.size());
    const auto count = static_cast<Index>(order.size());
    for (Index j = count - 1; j >= 0; --j) {
      const Found& f = order[std::size_t(j)];
      out.index.push_back(f.index);
      out.element.push_back(f.element ? 1 : 0);
      out.parent.push_back(f.parent < 0 ? -1 : base + (count - 1 - f.parent));
    }
    out.begin.push_back(static_cast<Index>(out.index.size()));
  }
  return out;
}

namespace detail {

namespace {

// At most this many elements to pins on one particle: more than three
// hard constraints on a particle's three coordinates are singular anyway.
constexpr int kMaxPins = 3;
using Mat6 = Eigen::Matrix<Real, 6, 6>;
using Vec6 = Eigen::Matrix<Real, 6, 1>;

// One tree's system (nodes b .. e - 1 of Model::trees, local index
// j = node - b). An element to a pin has one particle, its parent; it
// would be a leaf whose block is its compliance alone, 0 for a rigid link.
// So it is not eliminated alone: its particle's block takes it in, as a
// saddle-point block of up to 3 + kMaxPins rows,
//   [ D   H  ]
//   [ H^T -A ],
// H the pins' directions, A their compliances over h^2, solved by LU with
// full pivoting.
class TreeSystem {
 public:
  TreeSystem(const Model& m, State& s, Index t, bool stream, Real inv_h2)
      : m_(m), s_(s), ts_(s.tree), stream_(stream), inv_h2_(inv_h2) {
    b_ = std::size_t(m.trees.begin[std::size_t(t)]);
    e_ = std::size_t(m.trees.begin[std::size_t(t) + 1]);
    const std::size_t n = e_ - b_;
    if (ts_.d3.size() < n) {
      ts_.d3.resize(n);
      ts_.b3.resize(n);
      ts_.x3.resize(n);
      ts_.d1.resize(n);
      ts_.b1.resize(n);
      ts_.x1.resize(n);
      ts_.n.resize(n);
      ts_.sign.resize(n);
      ts_.pins.resize(n);
      ts_.pin_count.resize(n);
    }
  }

  // Every element's direction and residual at the current positions, and
  // each node's starting block; returns the largest |C + at lambda| / rest.
  Real assemble() {
    const Trees& tr = m_.trees;
    Real worst = 0;
    for (std::size_t j = 0; j < e_ - b_; ++j) ts_.pin_count[j] = 0;
    for (std::size_t j = 0; j < e_ - b_; ++j) {
      const std::size_t node = b_ + j;
      const Index i = tr.index[node];
      const Index parent = tr.parent[node];
      if (!tr.element[node]) {
        ts_.d3[j] = Mat3::Identity() / m_.inv_mass[std::size_t(i)];
        ts_.b3[j] = Vec3::Zero();
      } else {
        const Distance& e = m_.get<Distance>()[std::size_t(i)];
        const Vec3 d = s_.x[std::size_t(e.p[0])] - s_.x[std::size_t(e.p[1])];
        const Real len = d.norm();
        const Real at = e.mat.compliance * inv_h2_;
        if (len > kDegenerateRel * e.rest) {
          ts_.n[j] = d / len;
          ts_.d1[j] = -at;
          ts_.b1[j] = -(len - e.rest) - at * lambda_of(node);
          worst = std::max(worst, std::abs(ts_.b1[j]) / e.rest);
        } else {  // no direction: this element's dlambda is 0
          ts_.n[j] = Vec3::Zero();
          ts_.d1[j] = -1;
          ts_.b1[j] = 0;
        }
        // An element to a pin joins its particle's block.
        const bool to_pin = !(m_.inv_mass[std::size_t(e.p[0])] > Real(0)) || !(m_.inv_mass[std::size_t(e.p[1])] > Real(0));
        if (to_pin && parent >= 0) {
          const std::size_t pj = std::size_t(parent) - b_;
          if (ts_.pin_count[pj] < kMaxPins) ts_.pins[pj][std::size_t(ts_.pin_count[pj])] = Index(j);
          ++ts_.pin_count[pj];
        }
      }
      // The coupling with the parent: +n for an element's p[0], -n for its p[1].
      ts_.sign[j] = 1;
      if (parent >= 0) {
        const std::size_t ej = tr.element[node] ? node : std::size_t(parent);
        const std::size_t pj = tr.element[node] ? std::size_t(parent) : node;
        const Distance& e = m_.get<Distance>()[std::size_t(tr.index[ej])];
        ts_.sign[j] = e.p[0] == tr.index[pj] ? Real(1) : Real(-1);
      }
    }
    return worst;
  }

  // Eliminates from the leaves to the root, then solves from the root
  // back. False if a block is singular or a result not finite.
  bool solve() {
    const Trees& tr = m_.trees;
    // Leaves first: each node's block is final when it is reached; it is
    // folded into its parent's.
    for (std::size_t j = 0; j < e_ - b_; ++j) {
      const std::size_t node = b_ + j;
      const Index parent = tr.parent[node];
      const std::size_t pj = parent < 0 ? 0 : std::size_t(parent) - b_;
      if (!tr.element[node]) {
        if (ts_.pin_count[j] > kMaxPins) return false;
        // Coupling with the parent element, if any.
        const Vec3 g = parent < 0 ? Vec3(Vec3::Zero()) : Vec3(ts_.sign[j] * ts_.n[pj]);
        if (ts_.pin_count[j] == 0) {
          // The particle's mass plus n n^T / |d| of each child element:
          // symmetric positive definite.
          const Eigen::LLT<Mat3> llt(ts_.d3[j]);
          if (llt.info() != Eigen::Success) return false;
          if (parent < 0) continue;
          const Vec3 dg = llt.solve(g);
          ts_.d1[pj] -= g.dot(dg);
          ts_.b1[pj] -= dg.dot(ts_.b3[j]);
          continue;
        }
        Mat6 c;
        Vec6 rhs;
        block(j, c, rhs);
        const Eigen::FullPivLU<Mat6> lu(c);
        if (!lu.isInvertible()) return false;
        if (parent < 0) continue;
        Vec6 g6 = Vec6::Zero();
        g6.head<3>() = g;
        const Vec6 cg = lu.solve(g6);
        ts_.d1[pj] -= g6.dot(cg);
        ts_.b1[pj] -= cg.dot(rhs);
      } else {
        if (is_pin(node)) continue;  // in its particle's block
        const Real d = ts_.d1[j];
        if (!(std::abs(d) > Real(0)) || !std::isfinite(d)) return false;
        if (parent < 0) continue;
        const Vec3 h = ts_.sign[j] * ts_.n[j];  // coupling with the parent particle
        ts_.d3[pj] -= (h / d) * h.transpose();
        ts_.b3[pj] -= h * (ts_.b1[j] / d);
      }
    }
    // Root first: each node's solution from its parent's.
    for (std::size_t j = e_ - b_; j-- > 0;) {
      const std::size_t node = b_ + j;
      const Index parent = tr.parent[node];
      const std::size_t pj = parent < 0 ? 0 : std::size_t(parent) - b_;
      if (!tr.element[node]) {
        if (ts_.pin_count[j] == 0) {
          Vec3 r = ts_.b3[j];
          if (parent >= 0) r -= ts_.sign[j] * ts_.n[pj] * ts_.x1[pj];
          ts_.x3[j] = ts_.d3[j].llt().solve(r);
          if (!ts_.x3[j].allFinite()) return false;
          continue;
        }
        Mat6 c;
        Vec6 rhs;
        const int k = block(j, c, rhs);
        if (parent >= 0) rhs.head<3>() -= ts_.sign[j] * ts_.n[pj] * ts_.x1[pj];
        const Vec6 x = Eigen::FullPivLU<Mat6>(c).solve(rhs);
        if (!x.allFinite()) return false;
        ts_.x3[j] = x.head<3>();
        for (int q = 0; q < k; ++q) ts_.x1[std::size_t(ts_.pins[j][std::size_t(q)])] = x[3 + q];
      } else if (!is_pin(node)) {
        Real r = ts_.b1[j];
        if (parent >= 0) r -= ts_.sign[j] * ts_.n[j].dot(ts_.x3[pj]);
        ts_.x1[j] = r / ts_.d1[j];
        if (!std::isfinite(ts_.x1[j])) return false;
      }
    }
    return true;
  }

  // Moves the particles by their dx and adds each dlambda to its multiplier.
  void apply() {
    const Trees& tr = m_.trees;
    for (std::size_t j = 0; j < e_ - b_; ++j) {
      const std::size_t node = b_ + j;
      if (!tr.element[node])
        s_.x[std::size_t(tr.index[node])] += ts_.x3[j];
      else
        lambda_of(node) -= ts_.x1[j];
    }
  }

 private:
  // Whether element node `node` joins a pin (its particle's block).
  bool is_pin(std::size_t node) const {
    const Distance& e = m_.get<Distance>()[std::size_t(m_.trees.index[node])];
    return !(m_.inv_mass[std::size_t(e.p[0])] > Real(0)) || !(m_.inv_mass[std::size_t(e.p[1])] > Real(0));
  }
  // Particle node j's block with its pins (the rows past 3 + k are the
  // identity, with a zero right-hand side); returns k.
  int block(std::size_t j, Mat6& c, Vec6& rhs) const {
    const int k = std::min(ts_.pin_count[j], kMaxPins);
    c.setIdentity();
    rhs.setZero();
    c.topLeftCorner<3, 3>() = ts_.d3[j];
    rhs.head<3>() = ts_.b3[j];
    for (int q = 0; q < k; ++q) {
      const auto pe = std::size_t(ts_.pins[j][std::size_t(q)]);
      const Vec3 h = ts_.sign[pe] * ts_.n[pe];
      c.block<3, 1>(0, 3 + q) = h;
      c.block<1, 3>(3 + q, 0) = h.transpose();
      c(3 + q, 3 + q) = ts_.d1[pe];
      rhs[3 + q] = ts_.b1[pe];
    }
    return k;
  }
  Real& lambda_of(std::size_t node) {
    if (stream_) return s_.stream_lambda[std::size_t(m_.trees.stream_slot[node])];
    return s_.lambdas<Distance>()[std::size_t(m_.trees.index[node])];
  }

  const Model& m_;
  State& s_;
  TreeScratch& ts_;
  bool stream_;
  Real inv_h2_;
  std::size_t b_ = 0, e_ = 0;
};

}  // namespace

void trees_solve(const Model& m, State& s, Real h, bool stream, int passes, Real tol) {
  const Real inv_h2 = Real(1) / (h * h);
  for (Index t = 0; t < m.trees.size(); ++t) {
    TreeSystem sys(m, s, t, stream, inv_h2);
    newton_passes(sys, passes, tol);
  }
}

}  // namespace detail
}  // namespace xpbd
