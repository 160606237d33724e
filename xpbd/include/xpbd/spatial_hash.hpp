#pragma once
// Particle-particle collision between bodies and within one body
// (self-collision), found through a uniform-grid spatial hash
// (docs/design.md section 4, last row).
//
// Design
// ------
// Opt-in. SceneDesc::self_collision.enabled (scene.hpp) switches it on. A
// scene without it has no hash, no pair list and no pass: the arrays of
// Model::self_collision and State::self_collision stay empty and the two
// stage calls in step() return at once.
//
// Contact distance. One distance d (m) between particle centres for every
// pair, SelfCollisionDesc::distance, rather than the sum of the two radii:
// cloth particles usually carry a radius meant for planes and bodies, and
// one distance gives one cell size. A pair is in contact while
// |x_i - x_j| < d; it is the Collision element of constraints.hpp with
// rest = d (C = |x_i - x_j| - d >= 0), projected by the same kernel as the
// explicit pairs of SceneDesc::collisions. Frictionless, like them.
//
// Once per step, before the first substep (find_self_collisions):
//  1. Travel bound t_i (m) of every particle: how far it can move during
//     the step, t_i = |v| dt + max(|a| dt, |dv|) dt, where
//       - a = g + f/m is the external acceleration (0 for a kinematic
//         particle): symplectic Euler over n substeps moves a particle by
//         dt v + h^2 a n(n+1)/2, and h^2 n(n+1)/2 <= dt^2;
//       - dv is the particle's velocity change over the previous step, which
//         includes the constraint forces the external ones miss (a cloth
//         edge whipping, a particle pushed by a contact): the last step's
//         acceleration is assumed to persist for one more step. Under
//         external forces alone |dv| = |a| dt, so this adds nothing;
//     and for a kinematic particle with a pin, at least the move of its
//     pin target over the step.
//  2. Query radius r = d + 2 max_i t_i. A pair (i, j) that comes closer than
//     d at any time in the step starts it closer than d + t_i + t_j <= r.
//     The hash finds the pairs closer than r; those closer than
//     d + t_i + t_j are the step's candidates (the per-pair bound keeps one
//     fast particle from making every pair a candidate). Most candidates
//     never touch; one that does not costs one distance test per projection
//     (inequality: skipped while C >= 0 and lambda = 0).
//  3. Hash (build_spatial_hash): cell size r. Every particle's integer cell
//     c = floor(x / cell) is hashed into a table of 2^k >= 2n buckets, and a
//     counting sort writes the particle indices into one flat array grouped
//     by bucket, increasing within a bucket. No per-cell containers.
//     Particles with a non-finite position are left out (never in a pair).
//  4. Pairs (for_each_close_pair), cell by cell: for each occupied cell C,
//     the cells overlapping the box of its particles grown by r (3 per axis
//     when cell = r) that are not lexicographically before C (so each pair
//     of cells is visited once: 14 of the 27), and every particle pair
//     (one in C, one in that cell; i < j within C) with |x_i - x_j|^2 < r^2.
//     Stored cells are compared, so a bucket shared by two cells neither
//     repeats nor invents a pair. The bucket look-ups are shared by all the
//     particles of a cell.
//  5. A pair is kept if it is closer than d + t_i + t_j, unless both
//     particles are kinematic or the pair is excluded (below). The kept
//     pairs are put in (i, j) order by a counting sort on i and a sort of
//     each particle's few partners: the same input gives the same pairs in
//     the same order, whatever the hash table's size or the bucket order.
//
// Every iteration of every substep (solve_self_collisions) projects the
// pairs after all of the model's constraint types and before the rigid-body
// attachments and contacts; their multipliers restart at zero every substep
// like the others.
//
// Excluded pairs (Model::self_collision.exclude, built by compile()):
//  - always: the scene's explicit Collision pairs (already projected once);
//  - if skip_connected (the default): any two particles of one Distance,
//    DihedralBending or IsometricBending element (a hinge is its two
//    triangles), TetVolume, or GlobalVolume triangle. Their distance is the
//    business of that constraint; without this a cloth whose edges are
//    shorter than d would fight its own edges. Where the edges of a mesh are
//    Distance elements (every builder in builders.hpp), "sharing a triangle"
//    is covered by this.
// Stored in CSR form by lower index: the excluded partners j > i of
// particle i are exclude[exclude_begin[i] .. exclude_begin[i+1]), sorted,
// found by binary search.
//
// Limits (documented, not checked):
//  - The margin is a prediction, not a bound: a particle whose acceleration
//    jumps within a step (a sudden constraint or rigid-contact push) can
//    move further than t_i and meet a particle that is not a candidate; the
//    next step finds the pair.
//  - Contacts are discrete in the substeps: two particles whose relative
//    move in one substep exceeds about 2d can pass through each other.
//  - Cell coordinates are clamped to +-2^30 cells, so positions beyond
//    2^30 cell sizes from the origin share cells (still correct, slower).
//
// Memory. make_state() sizes the hash and per-particle arrays (n entries and
// 2^k + 1 buckets) and reserves 4n entries in the pair arrays (`found`,
// `pairs`, `lambda`). A step that finds more pairs than any before grows
// them (std::vector doubling, so amortized and rare); otherwise step()
// allocates nothing here.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "xpbd/constraints.hpp"
#include "xpbd/types.hpp"

namespace xpbd {

struct Model;
struct State;
struct SceneDesc;
struct StepConfig;
struct SolveContext;

// ---------------------------------------------------------------------------
// Uniform-grid spatial hash over a point set

using Cell = std::array<std::int32_t, 3>;

struct SpatialHash {
  Real cell = 0;                  // m, cell edge length (> 0)
  Real inv_cell = 0;              // 1/m
  std::vector<Cell> cell_of;      // integer cell of each point
  std::vector<Index> bucket_begin;  // 2^k + 1 offsets into `sorted`
  std::vector<Index> sorted;      // finite points' indices grouped by bucket, increasing within one
};

namespace detail {
inline constexpr Real kMaxCell = Real(1 << 30);

// floor(x / cell) per axis, as x * (1/cell): monotone in x, which is what
// makes the query box below catch every point it must. Clamped to
// [-2^30, 2^30]; NaN goes to -2^30.
inline Cell cell_at(const Vec3& x, Real inv_cell) {
  Cell c{};
  for (int a = 0; a < 3; ++a) {
    // Clamped first, then rounded down by truncation, one less where that
    // rounded a negative number up: the same as std::floor, then the
    // clamp, for every value (a NaN too). std::floor is a call into libm
    // on x86-64 without SSE4.1, three per point: the bridge's pair search
    // took 0.82 times as long without it (docs/search-costs.md).
    Real v = x[a] * inv_cell;
    if (!(v >= -kMaxCell)) v = -kMaxCell;
    if (v > kMaxCell) v = kMaxCell;
    auto i = static_cast<std::int32_t>(v);
    if (static_cast<Real>(i) > v) --i;
    c[std::size_t(a)] = i;
  }
  return c;
}

// Bucket of a cell: the three coordinates times large odd constants, XORed
// (Teschner et al. 2003), masked to the power-of-two table size. Unsigned
// arithmetic, so the wrap-around is defined.
inline std::uint32_t bucket_of(const Cell& c, std::uint32_t mask) {
  const std::uint32_t h = (static_cast<std::uint32_t>(c[0]) * 73856093u) ^
                          (static_cast<std::uint32_t>(c[1]) * 19349663u) ^
                          (static_cast<std::uint32_t>(c[2]) * 83492791u);
  return h & mask;
}
}  // namespace detail

// Rebuilds h over the points x with cell edge `cell` (m, > 0 and finite).
// Points with a non-finite coordinate are left out. Allocates only when the
// number of points grew since the last build.
void build_spatial_hash(SpatialHash& h, std::span<const Vec3> x, Real cell);

namespace detail {
inline bool same_cell(const Cell& a, const Cell& b) {
  // Component by component (std::array's == calls memcmp).
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}
inline bool cell_less(const Cell& a, const Cell& b) {
  if (a[2] != b[2]) return a[2] < b[2];
  if (a[1] != b[1]) return a[1] < b[1];
  return a[0] < b[0];
}
}  // namespace detail

// Calls f(i, j) exactly once for every pair i < j of the points h was built
// over (h must have been built over these x) with
// (x_i - x_j).squaredNorm() < r * r (r in m, >= 0). Any cell size works;
// the work per cell grows as (2r/cell + 2)^3 cells. The order of the calls
// is deterministic but otherwise unspecified.
//
// Why no pair is missed: if the predicate holds then |fl(x_j - x_i)| < r on
// every axis, so |x_j - x_i| < r (1 + eps) exactly, and x_j lies inside the
// box [x_i - rb, x_i + rb] with rb = r (1 + kDegenerateRel), and x_i inside
// the same box around x_j. cell_at is monotone, so each point's cell lies
// in the range of cells the other's cell visits, and the pair is found from
// whichever of the two cells comes first.
template <class F>
void for_each_close_pair(const SpatialHash& h, std::span<const Vec3> x, Real r, F&& f) {
  if (h.bucket_begin.size() < 2) return;
  const std::size_t table = h.bucket_begin.size() - 1;
  const auto mask = static_cast<std::uint32_t>(table - 1);
  const Real r2 = r * r;
  const Real rb = r * (Real(1) + kDegenerateRel);
  const Vec3 box(rb, rb, rb);
  const Index* const sorted = h.sorted.data();
  const Cell* const cell_of = h.cell_of.data();
  for (std::size_t b = 0; b < table; ++b) {
    const Index b0 = h.bucket_begin[b], b1 = h.bucket_begin[b + 1];
    for (Index k0 = b0; k0 < b1; ++k0) {
      const Cell c = cell_of[sorted[k0]];
      // Only from the cell's first entry in this bucket.
      bool seen = false;
      for (Index k = b0; k < k0 && !seen; ++k) seen = detail::same_cell(cell_of[sorted[k]], c);
      if (seen) continue;
      // Bounding box of the cell's points, grown by rb: the cells to visit.
      Vec3 lo = x[std::size_t(sorted[k0])], hi = lo;
      for (Index k = k0 + 1; k < b1; ++k)
        if (detail::same_cell(cell_of[sorted[k]], c)) {
          lo = lo.cwiseMin(x[std::size_t(sorted[k])]);
          hi = hi.cwiseMax(x[std::size_t(sorted[k])]);
        }
      const Cell clo = detail::cell_at(lo - box, h.inv_cell);
      const Cell chi = detail::cell_at(hi + box, h.inv_cell);
      Cell nc;
      for (nc[2] = clo[2]; nc[2] <= chi[2]; ++nc[2])
        for (nc[1] = clo[1]; nc[1] <= chi[1]; ++nc[1])
          for (nc[0] = clo[0]; nc[0] <= chi[0]; ++nc[0]) {
            if (detail::cell_less(nc, c)) continue;  // visited from nc's side
            const bool self = detail::same_cell(nc, c);
            const std::uint32_t bn = detail::bucket_of(nc, mask);
            const Index n1 = h.bucket_begin[bn + 1];
            for (Index kj = h.bucket_begin[bn]; kj < n1; ++kj) {
              const Index j = sorted[kj];
              if (!detail::same_cell(cell_of[j], nc)) continue;
              const Vec3 xj = x[std::size_t(j)];
              for (Index ki = k0; ki < b1; ++ki) {
                const Index i = sorted[ki];
                if (self && i >= j) break;  // same cell: i < j only (i increases)
                if (!detail::same_cell(cell_of[i], c)) continue;
                if ((x[std::size_t(i)] - xj).squaredNorm() < r2) {
                  if (i < j)
                    f(i, j);
                  else
                    f(j, i);
                }
              }
            }
          }
    }
  }
}

// ---------------------------------------------------------------------------
// Self-collision: compiled data (Model side) and per-step data (State side)

struct SelfCollisionModel {
  bool enabled = false;
  Real distance = 0;  // m, contact distance between particle centres (> 0 when enabled)
  Material mat;       // compliance m/N, damping N*s/m, PBD stiffness
  // Excluded partners in CSR form: the partners j > i of particle i are
  // exclude[exclude_begin[i] .. exclude_begin[i+1]), increasing. Empty when
  // disabled; n + 1 entries in exclude_begin otherwise.
  std::vector<Index> exclude_begin;
  std::vector<Index> exclude;

  // True if pair (i, j), i < j, is excluded.
  bool excluded(Index i, Index j) const {
    const auto first = exclude.begin() + exclude_begin[std::size_t(i)];
    const auto last = exclude.begin() + exclude_begin[std::size_t(i) + 1];
    return std::binary_search(first, last, j);
  }
};

struct SelfCollisionState {
  SpatialHash hash;
  std::vector<Collision> pairs;  // candidates of the current step, sorted by (p[0], p[1])
  std::vector<Real> lambda;      // kg*m, parallel to pairs (force = lambda / h^2, N)
  std::vector<Real> travel;      // m, travel bound t_i of every particle this step
  std::vector<Vec3> v_last;      // m/s, velocities at the start of the previous step
  // Scratch of the pair search: pairs in the hash's order, and the start of
  // each particle's pairs in `pairs` (n + 1 entries).
  std::vector<std::array<Index, 2>> found;
  std::vector<Index> first;
  Real radius = 0;               // m, query radius r = d + 2 max t_i of the current step
};

// compile(): builds m.self_collision from s.self_collision and the model's
// constraint arrays (call after they are compiled; s.self_collision is
// already validated).
void compile_self_collision(const SceneDesc& s, Model& m);

// make_state(): sizes the hash and reserves the pair arrays (nothing when
// disabled).
void init_self_collision(const Model& m, State& s);

// step(), once before the substeps: rebuilds the hash and the pair list.
void find_self_collisions(const Model& m, State& s, const StepConfig& cfg);

// step(), every iteration: one Gauss-Seidel projection of the pairs.
void solve_self_collisions(const Model& m, State& s, const SolveContext& sc);

}  // namespace xpbd
