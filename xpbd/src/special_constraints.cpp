#include "xpbd/special_constraints.hpp"

#include <algorithm>
#include <string>

#include "xpbd/error.hpp"

namespace xpbd {

void begin_step_constraints(const Model& m, State& s) {
  const std::size_t pen = m.get<Penetration>().size();
  if (s.penetration_side.size() != pen)
    throw ConfigError("state.penetration_side: has " + std::to_string(s.penetration_side.size()) +
                      " entries, model has " + std::to_string(pen) +
                      " penetration constraints (use make_state)");
  if (s.volume_grad.size() != m.global_volume_verts.size())
    throw ConfigError("state.volume_grad: has " + std::to_string(s.volume_grad.size()) +
                      " entries, model has " + std::to_string(m.global_volume_verts.size()) +
                      " global-volume vertices (use make_state)");
  record_penetration_sides(m, s);
}

void record_penetration_sides(const Model& m, State& s) {
  const auto& pen = m.get<Penetration>();
  for (std::size_t k = 0; k < pen.size(); ++k) s.penetration_side[k] = Penetration::side(pen[k], s.x.data());
}

Real global_volume(const Model& m, const GlobalVolume& g, const Vec3* x, Vec3* grad) {
  const Index* verts = m.global_volume_verts.data();
  const Vec3 origin = x[verts[g.vert_begin]];
  if (grad) std::fill(grad + g.vert_begin, grad + g.vert_end, Vec3::Zero());
  Real six_v = 0;
  for (Index t = g.tri_begin; t < g.tri_end; ++t) {
    const auto& tri = m.global_volume_tris[t];
    const Vec3 a = x[verts[tri[0]]] - origin;
    const Vec3 b = x[verts[tri[1]]] - origin;
    const Vec3 c = x[verts[tri[2]]] - origin;
    const Vec3 bc = b.cross(c);
    six_v += a.dot(bc);
    if (grad) {
      grad[tri[0]] += bc;
      grad[tri[1]] += c.cross(a);
      grad[tri[2]] += a.cross(b);
    }
  }
  constexpr Real sixth = Real(1) / Real(6);
  if (grad)
    for (Index v = g.vert_begin; v < g.vert_end; ++v) grad[v] *= sixth;
  return six_v * sixth;
}

namespace {

// Same update as project_all (solve.hpp) for one equality constraint whose
// gradient is in grad[g.vert_begin, g.vert_end).
template <bool kDamped>
void project_volumes(const Model& m, State& s, const SolveContext& sc) {
  const auto& vols = m.get<GlobalVolume>();
  auto& lambda = s.lambdas<GlobalVolume>();
  const Index* verts = m.global_volume_verts.data();
  Vec3* grad = s.volume_grad.data();
  const bool xpbd = sc.method == Method::xpbd;
  const Real inv_h = Real(1) / sc.h;
  for (std::size_t k = 0; k < vols.size(); ++k) {
    const GlobalVolume& g = vols[k];
    const Real C = global_volume(m, g, sc.x, grad) - g.target;
    Real wg = 0;
    for (Index v = g.vert_begin; v < g.vert_end; ++v)
      wg += sc.inv_mass[verts[v]] * grad[v].squaredNorm();
    Real dl;
    if (xpbd) {
      const Real at = g.mat.compliance * inv_h * inv_h;
      Real num = -C - at * lambda[k];
      Real den = wg + at;
      if constexpr (kDamped) {
        const Real gamma = g.mat.compliance * g.mat.damping * inv_h;
        Real gv = 0;
        for (Index v = g.vert_begin; v < g.vert_end; ++v)
          gv += grad[v].dot(sc.x[verts[v]] - sc.x_prev[verts[v]]);
        num -= gamma * gv;
        den += gamma * wg;
      }
      if (!(den > Real(0))) continue;
      dl = num / den;
    } else {
      if (!(wg > Real(0))) continue;
      dl = -g.mat.stiffness * C / wg;
    }
    lambda[k] += dl;
    for (Index v = g.vert_begin; v < g.vert_end; ++v)
      sc.x[verts[v]] += (sc.inv_mass[verts[v]] * dl) * grad[v];
  }
}

}  // namespace

void solve_global_volumes(const Model& m, State& s, const SolveContext& sc) {
  if (m.get<GlobalVolume>().empty()) return;
  if (m.has_damping[type_index_v<GlobalVolume>])
    project_volumes<true>(m, s, sc);
  else
    project_volumes<false>(m, s, sc);
}

}  // namespace xpbd
