// The coloured XPBD DihedralBending sweep over Model::dihedral_stream
// (dihedral_stream.hpp; kernel in dihedral_kernel.hpp).
#include <string>

#include "dihedral_kernel.hpp"
#include "stream.hpp"
#include "xpbd/dihedral_stream.hpp"
#include "xpbd/error.hpp"

namespace xpbd {
namespace detail {

void project_dihedral_scalar(const DihedralArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first) {
  project_dihedral_variant<ScalarLane>(s, lo, hi, damped, first);
}

namespace {
using Kernel = void (*)(const DihedralArgs&, std::size_t, std::size_t, bool, bool);

Kernel kernel(bool simd) {
#if XPBD_HAVE_AVX2_KERNEL
  const Kernel avx2 = &project_dihedral_avx2;
#else
  const Kernel avx2 = nullptr;
#endif
#if XPBD_HAVE_AVX512_KERNEL
  const Kernel avx512 = &project_dihedral_avx512;
#else
  const Kernel avx512 = nullptr;
#endif
  return pick_kernel(simd_level(simd), &project_dihedral_scalar, avx2, avx512);
}
}  // namespace

void dihedral_begin_step(const Model& m, State& s, Real h, Workers* workers) {
  const DihedralStream& ds = m.dihedral_stream;
  const std::size_t e = ds.size();
  const bool damped = m.has_damping[type_index_v<DihedralBending>];
  size_records(m, s, damped);
  s.dihedral_at.resize(e);
  s.dihedral_gamma.resize(damped ? e : 0);
  s.dihedral_lambda.resize(e);
  const Real inv_h = Real(1) / h;
  const Real inv_h2 = inv_h * inv_h;
  split(workers, e, 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t j = lo; j < hi; ++j) {
      s.dihedral_at[j] = ds.compliance[j] * inv_h2;
      if (damped) s.dihedral_gamma[j] = (ds.compliance[j] * ds.damping[j]) * inv_h;
    }
  });
}

void dihedral_sweep(const Model& m, State& s, const SolveContext& sc, bool damped, bool simd, bool first,
                    bool pack, Workers* workers) {
  const DihedralStream& ds = m.dihedral_stream;
  if (pack) pack_records(m, s, damped, workers);
  DihedralArgs a;
  a.p[0] = ds.p0.data(), a.p[1] = ds.p1.data(), a.p[2] = ds.p2.data(), a.p[3] = ds.p3.data();
  a.rest = ds.rest.data();
  a.at = s.dihedral_at.data();
  a.gamma = s.dihedral_gamma.data();
  a.lambda = s.dihedral_lambda.data();
  a.x = s.stream_x.data();
  a.x_prev = damped ? s.stream_x_prev.data() : nullptr;
  const Kernel k = kernel(simd);
  // The colours, then the records back into s.x.
  sweep_colours_then(
      m.dihedral_colours, sc.reverse, workers, [&](std::size_t lo, std::size_t hi) { k(a, lo, hi, damped, first); },
      kMinPerTask, s.x.size(), [&](std::size_t lo, std::size_t hi) { unpack_range(s, lo, hi); });
}

void dihedral_end_step(const Model& m, State& s) {
  scatter_lambda(m.dihedral_colours.order, s.dihedral_lambda, s.lambdas<DihedralBending>());
}

DihedralStream make_dihedral_stream(const Model& m) {
  DihedralStream ds;
  const auto& d = m.get<DihedralBending>();
  const auto& order = m.dihedral_colours.order;
  const std::size_t n = order.size();
  ds.p0.resize(n), ds.p1.resize(n), ds.p2.resize(n), ds.p3.resize(n);
  ds.rest.resize(n), ds.compliance.resize(n), ds.damping.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const DihedralBending& c = d[static_cast<std::size_t>(order[j])];
    ds.p0[j] = c.p[0], ds.p1[j] = c.p[1], ds.p2[j] = c.p[2], ds.p3[j] = c.p[3];
    ds.rest[j] = c.rest_angle, ds.compliance[j] = c.mat.compliance, ds.damping[j] = c.mat.damping;
  }
  return ds;
}

}  // namespace detail

void project_dihedral_stream(const Model& m, State& s, const SolveContext& sc, bool simd, Workers* workers) {
  const std::size_t e = m.dihedral_stream.size();
  const bool damped = m.has_damping[type_index_v<DihedralBending>];
  if (e != m.get<DihedralBending>().size() || s.dihedral_at.size() != e || s.dihedral_lambda.size() != e ||
      s.stream_x.size() != 4 * static_cast<std::size_t>(m.num_particles()) ||
      (damped && (s.dihedral_gamma.size() != e || s.stream_x_prev.size() != s.stream_x.size())))
    throw ConfigError(
        "project_dihedral_stream: the state's stream is not prepared for this model (call prepare_stream)");
  detail::dihedral_sweep(m, s, sc, damped, simd, false, true, workers);
}

}  // namespace xpbd
