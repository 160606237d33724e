#include "xpbd/spatial_hash.hpp"

#include <bit>
#include <string>

#include "xpbd/error.hpp"
#include "xpbd/model.hpp"
#include "xpbd/scene.hpp"
#include "xpbd/solve.hpp"
#include "xpbd/state.hpp"
#include "xpbd/step.hpp"

namespace xpbd {

void build_spatial_hash(SpatialHash& h, std::span<const Vec3> x, Real cell) {
  const std::size_t n = x.size();
  // Table of 2^k >= 2n buckets: on average at most half a point per bucket.
  const std::size_t table = std::bit_ceil(std::max<std::size_t>(2 * n, 1));
  const auto mask = static_cast<std::uint32_t>(table - 1);
  h.cell = cell;
  h.inv_cell = Real(1) / cell;
  h.cell_of.resize(n);
  h.bucket_begin.assign(table + 1, 0);  // same size as before: no allocation

  // Counting sort by bucket. Count into bucket_begin[b + 1] ...
  for (std::size_t i = 0; i < n; ++i) {
    h.cell_of[i] = detail::cell_at(x[i], h.inv_cell);
    if (x[i].allFinite()) ++h.bucket_begin[detail::bucket_of(h.cell_of[i], mask) + 1];
  }
  // ... prefix sums: bucket_begin[b] = start of bucket b ...
  for (std::size_t b = 0; b < table; ++b) h.bucket_begin[b + 1] += h.bucket_begin[b];
  h.sorted.resize(std::size_t(h.bucket_begin[table]));  // finite points only
  // ... scatter in increasing index order, using bucket_begin[b] as bucket
  // b's write cursor (it ends at the start of bucket b + 1) ...
  for (std::size_t i = 0; i < n; ++i)
    if (x[i].allFinite())
      h.sorted[std::size_t(h.bucket_begin[detail::bucket_of(h.cell_of[i], mask)]++)] =
          static_cast<Index>(i);
  // ... and shift the cursors back into starts.
  for (std::size_t b = table; b > 0; --b) h.bucket_begin[b] = h.bucket_begin[b - 1];
  h.bucket_begin[0] = 0;
}

void compile_self_collision(const SceneDesc& s, Model& m) {
  const SelfCollisionDesc& d = s.self_collision;
  SelfCollisionModel& out = m.self_collision;
  out = SelfCollisionModel{};
  if (!d.enabled) return;
  out.enabled = true;
  out.distance = d.distance;
  out.mat = d.mat;

  // Excluded pairs (lower index first), then sorted and deduplicated.
  std::vector<std::array<Index, 2>> ex;
  auto add = [&](Index a, Index b) {
    if (a != b) ex.push_back({std::min(a, b), std::max(a, b)});
  };
  auto add_all = [&](const auto& p) {  // every pair of one element's particles
    for (std::size_t u = 0; u < p.size(); ++u)
      for (std::size_t v = u + 1; v < p.size(); ++v) add(p[u], p[v]);
  };
  for (const Collision& c : m.get<Collision>()) add_all(c.p);
  if (d.skip_connected) {
    for (const Distance& c : m.get<Distance>()) add_all(c.p);
    for (const DihedralBending& c : m.get<DihedralBending>()) add_all(c.p);
    for (const IsometricBending& c : m.get<IsometricBending>()) add_all(c.p);
    for (const TetVolume& c : m.get<TetVolume>()) add_all(c.p);
    for (const auto& tri : m.global_volume_tris)  // vertex slots -> particles
      add_all(std::array<Index, 3>{m.global_volume_verts[std::size_t(tri[0])],
                                   m.global_volume_verts[std::size_t(tri[1])],
                                   m.global_volume_verts[std::size_t(tri[2])]});
  }
  std::sort(ex.begin(), ex.end());
  ex.erase(std::unique(ex.begin(), ex.end()), ex.end());

  const auto n = static_cast<std::size_t>(m.num_particles());
  out.exclude_begin.assign(n + 1, 0);
  for (const auto& e : ex) ++out.exclude_begin[std::size_t(e[0]) + 1];
  for (std::size_t i = 0; i < n; ++i) out.exclude_begin[i + 1] += out.exclude_begin[i];
  out.exclude.reserve(ex.size());
  for (const auto& e : ex) out.exclude.push_back(e[1]);  // sorted by (i, j): CSR order
}

void init_self_collision(const Model& m, State& s) {
  SelfCollisionState& sc = s.self_collision;
  sc = SelfCollisionState{};
  if (!m.self_collision.enabled) return;
  // An empty build sizes the arrays; the first step fills them.
  const auto n = static_cast<std::size_t>(m.num_particles());
  build_spatial_hash(sc.hash, std::span<const Vec3>(s.x), m.self_collision.distance);
  sc.travel.assign(n, Real(0));
  sc.v_last = s.v;
  sc.first.assign(n + 1, 0);
  sc.found.reserve(4 * n);
  sc.pairs.reserve(4 * n);
  sc.lambda.reserve(4 * n);
}

void find_self_collisions(const Model& m, State& s, const StepConfig& cfg) {
  const SelfCollisionModel& sm = m.self_collision;
  SelfCollisionState& sc = s.self_collision;
  if (!sm.enabled) return;

  // 1. Travel bounds t_i (see the header).
  const Index n = m.num_particles();
  const Real dt = cfg.dt;
  const bool forces = !s.f_ext.empty();
  // Sized by make_state: no allocation (a State built otherwise gets them
  // here, once).
  sc.travel.resize(std::size_t(n));
  if (sc.v_last.size() != std::size_t(n)) sc.v_last = s.v;
  Real* const travel = sc.travel.data();
  for (Index i = 0; i < n; ++i) {
    Vec3 a = Vec3::Zero();
    if (m.inv_mass[i] > Real(0)) {
      a = cfg.gravity;
      if (forces) a += m.inv_mass[i] * s.f_ext[i];
    }
    const Real dv = (s.v[i] - sc.v_last[i]).norm();  // m/s, over the previous step
    const Real ti = s.v[i].norm() * dt + std::max(a.norm() * dt, dv) * dt;
    if (!std::isfinite(ti))
      throw ConfigError("state.v[" + std::to_string(i) +
                        "]: velocity or external force is not finite, so self-collision cannot "
                        "bound the particle's travel");
    travel[i] = ti;
  }
  const auto& pins = m.get<Pin>();
  for (std::size_t k = 0; k < pins.size(); ++k) {
    const Index i = pins[k].p[0];
    if (m.inv_mass[i] != Real(0)) continue;
    const Real move = (s.pin_target[k] - s.x[i]).norm();
    if (!std::isfinite(move))
      throw ConfigError("state.pin_target[" + std::to_string(k) +
                        "]: the target or its particle's position is not finite, so "
                        "self-collision cannot bound the particle's travel");
    travel[i] = std::max(travel[i], move);
  }
  // Only now, with every input checked: this step's velocities become the
  // previous ones of the next step.
  std::copy(s.v.begin(), s.v.end(), sc.v_last.begin());
  // 2. Query radius, 3. hash with cell size r.
  const Real t = n > 0 ? *std::max_element(travel, travel + n) : Real(0);
  const Real d = sm.distance;
  const Real r = d + 2 * t;
  sc.radius = r;
  const std::span<const Vec3> x(s.x);
  build_spatial_hash(sc.hash, x, r);

  // 4. Pairs within r, in the hash's order (a light callback: the search
  //    loop stays tight) ...
  auto& found = sc.found;
  found.clear();
  for_each_close_pair(sc.hash, x, r, [&found](Index i, Index j) { found.push_back({i, j}); });
  // 5. ... kept if within d + t_i + t_j, not both kinematic (nothing could
  //    move) and not excluded ...
  std::size_t kept = 0;
  for (const auto& p : found) {
    const Index i = p[0], j = p[1];
    if (m.inv_mass[i] == Real(0) && m.inv_mass[j] == Real(0)) continue;
    const Real rij = d + travel[i] + travel[j];
    if (!((x[std::size_t(i)] - x[std::size_t(j)]).squaredNorm() < rij * rij)) continue;
    if (sm.excluded(i, j)) continue;
    found[kept++] = p;
  }
  found.resize(kept);
  // ... then put in (i, j) order: counting sort on i (first[i] = start of
  // particle i's pairs, used as its write cursor and shifted back), then
  // each particle's few partners sorted by j.
  std::vector<Index>& first = sc.first;
  first.assign(std::size_t(n) + 1, 0);  // same size every step: no allocation
  for (const auto& p : sc.found) ++first[std::size_t(p[0]) + 1];
  for (std::size_t i = 0; i < std::size_t(n); ++i) first[i + 1] += first[i];
  sc.pairs.resize(sc.found.size());
  for (const auto& p : sc.found)
    sc.pairs[std::size_t(first[std::size_t(p[0])]++)] = Collision{{p[0], p[1]}, d, sm.mat};
  for (std::size_t i = std::size_t(n); i > 0; --i) first[i] = first[i - 1];
  first[0] = 0;
  for (std::size_t i = 0; i < std::size_t(n); ++i)
    std::sort(sc.pairs.begin() + first[i], sc.pairs.begin() + first[i + 1],
              [](const Collision& a, const Collision& b) { return a.p[1] < b.p[1]; });
  sc.lambda.resize(sc.pairs.size());  // zeroed every substep by step()
}

void solve_self_collisions(const Model& m, State& s, const SolveContext& sc) {
  SelfCollisionState& st = s.self_collision;
  if (st.pairs.empty()) return;
  const std::span<const Collision> pairs(st.pairs);
  if (m.self_collision.mat.damping != Real(0))
    project_all<Collision, true>(pairs, st.lambda, sc);
  else
    project_all<Collision, false>(pairs, st.lambda, sc);
}

}  // namespace xpbd
