#pragma once
// The prediction pass of step() (step.cpp, predict) as flat arrays, for its
// AVX-512 kernel (predict_avx512.cpp). Per particle i, in this order:
//   before = 1: v = (x - x_prev) * scale
//   before = 2: m = (x - x_prev) * inv_h; v = (w > 0 ? v + blend (m - v) : m) * keep
//   x_prev = x; if w > 0: v = v + h (g + w f); x = x + h v
//   rec (if set) = (x, y, z, w) of the new x; rec_prev (if set) = the same of x_prev
// with the same operations in the same order as the scalar loop, so the
// same bits (no FMA: the kernel's file is built with -ffp-contract=off).
#include <cstddef>

#include "xpbd/types.hpp"

namespace xpbd::detail {

struct PredictArgs {
  Real* x = nullptr;  // 3 per particle (std::vector<Vec3>'s storage)
  Real* x_prev = nullptr;
  Real* v = nullptr;
  const Real* inv_mass = nullptr;
  const Real* f = nullptr;  // 3 per particle, or null
  Real g[3] = {0, 0, 0};
  Real h = 0;
  int before = 0;  // 0: none, 1: plain velocity update, 2: blended (above)
  Real scale = 0, inv_h = 0, keep = 1, blend = 1;
  Real* rec = nullptr;       // 4 per particle, or null
  Real* rec_prev = nullptr;  // 4 per particle, or null (only with rec)
};

// The test StepConfig::refresh_contacts makes after every prediction
// (refresh_paths.cpp, refresh_escaped), as a filter that proves no particle of a
// batch left its path: per coordinate c of a movable particle i (w != 0),
//   d = x - (path_x + (t_end - path_t) * path_v),  flagged unless d^2 <= bound2.
// With bound2 a little under margin^2 / 3, a batch with no coordinate
// flagged has every particle within the margin (the exact test then finds
// none); a flagged one is left to the exact test.
struct PathArgs {
  const Real* x = nullptr;  // 3 per particle
  const Real* path_x = nullptr;
  const Real* path_v = nullptr;
  const Real* path_t = nullptr;  // 1 per particle
  const Real* inv_mass = nullptr;
  Real t_end = 0;   // s
  Real bound2 = 0;  // m^2, per coordinate
};

#if XPBD_HAVE_AVX512_KERNEL
// Runs the pass over whole batches of particles from lo (16 in float, 8 in
// double) and returns where it stopped; the caller runs the rest.
std::size_t predict_avx512(const PredictArgs& a, std::size_t lo, std::size_t hi);

// The path filter over whole batches from lo: returns where it stopped,
// at the end of the first flagged batch, whose start goes to `batch`, or
// after the last whole batch (then batch = the value returned).
std::size_t off_path_avx512(const PathArgs& a, std::size_t lo, std::size_t hi, std::size_t& batch);
#endif

}  // namespace xpbd::detail
