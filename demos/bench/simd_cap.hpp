#pragma once
// The AVX2-capped rows of the kernel benchmarks (bench_distance,
// bench_dihedral, bench_tethers): on a CPU where the coloured sweeps run
// the AVX-512 kernel, the same sweep capped at AVX2 (xpbd::set_simd_kernel)
// runs beside it, so the two kernels are compared in one run; and the cap
// of a whole run from the environment.
#include <cstdlib>
#include <string>

#include "xpbd/distance_stream.hpp"

namespace xpbd_bench {

// The widest stream kernel, before any cap.
inline const std::string& widest_kernel() {
  static const std::string widest = xpbd::simd_kernel();
  return widest;
}

// True where an AVX2-capped row means something (the widest is AVX-512).
inline bool has_avx2_row() { return widest_kernel() == "avx512"; }

// Caps the stream kernels at AVX2 while it lives if `on`.
class Avx2Cap {
 public:
  explicit Avx2Cap(bool on) : on_(on) {
    if (on_) xpbd::set_simd_kernel("avx2");
  }
  ~Avx2Cap();
  Avx2Cap(const Avx2Cap&) = delete;
  Avx2Cap& operator=(const Avx2Cap&) = delete;

 private:
  bool on_;
};

// The cap named by the environment variable XPBD_BENCH_SIMD ("avx512",
// "avx512-ymm", "avx2", "scalar" or "auto"; any name xpbd::set_simd_kernel
// takes), or none (auto) without it: the whole run at that kernel
// (bench_scale), or every row but the AVX2-capped ones (bench_distance).
// Throws xpbd::ConfigError for a name the library refuses.
inline void cap_from_environment() {
  const char* name = std::getenv("XPBD_BENCH_SIMD");
  xpbd::set_simd_kernel(name != nullptr ? name : "auto");
}

// Back to the run's cap: the environment's, or none.
inline Avx2Cap::~Avx2Cap() {
  if (on_) cap_from_environment();
}

}  // namespace xpbd_bench
