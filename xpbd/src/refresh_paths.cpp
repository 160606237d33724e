// StepConfig::refresh_contacts (refresh_paths.hpp).
#include "refresh_paths.hpp"

#include <limits>
#include <span>

#include "predict_kernel.hpp"
#include "stream.hpp"

namespace xpbd::detail {

void begin_paths(const Model& m, State& s) {
  s.path_x = s.x;
  s.path_v = s.v;
  s.path_t.assign(static_cast<std::size_t>(m.num_particles()), Real(0));
}

bool refresh_escaped(const Model& m, State& s, const StepConfig& cfg, int sub, Real h) {
  const Real t_end = Real(sub + 1) * h, t_start = Real(sub) * h;
  const Real margin2 = cfg.contact_margin * cfg.contact_margin;
  s.escaped.clear();
  // The exact test of particles [lo, hi), in order.
  const auto exact = [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      if (m.inv_mass[i] == Real(0)) continue;
      const Vec3 on_path = s.path_x[i] + (t_end - s.path_t[i]) * s.path_v[i];
      if (!((s.x[i] - on_path).squaredNorm() <= margin2)) {
        s.escaped.push_back(static_cast<Index>(i));
        s.path_x[i] = s.x_prev[i];
        s.path_v[i] = s.v[i];
        s.path_t[i] = t_start;
      }
    }
  };
  std::size_t from = 0;  // the exact test runs from here to the end
#if XPBD_HAVE_AVX512_KERNEL
  // Most particles stay on their path: the AVX-512 filter
  // (predict_kernel.hpp, PathArgs) proves that for whole batches at a
  // fraction of the exact test's cost, and leaves a batch it cannot clear
  // to the exact test. Its bound leaves room for the exact test's
  // round-off (a sum of 3 squares), so it never clears a particle the test
  // would pass.
  if (detail::simd_level(cfg.simd) == detail::Simd::avx512 && !s.x.empty()) {
    detail::PathArgs a;
    a.x = s.x.front().data();
    a.path_x = s.path_x.front().data();
    a.path_v = s.path_v.front().data();
    a.path_t = s.path_t.data();
    a.inv_mass = m.inv_mass.data();
    a.t_end = t_end;
    a.bound2 = margin2 / Real(3) * (Real(1) - Real(16) * std::numeric_limits<Real>::epsilon());
    for (;;) {
      std::size_t batch = 0;
      const std::size_t stop = detail::off_path_avx512(a, from, s.x.size(), batch);
      if (batch == stop) {  // no batch flagged up to stop
        from = stop;
        break;
      }
      exact(batch, stop);
      from = stop;
    }
  }
#endif
  exact(from, s.x.size());
  if (s.escaped.empty()) return false;
  cfg.refresh_contacts(std::span<const Index>(s.escaped), sub);
  return true;
}

}  // namespace xpbd::detail
