#pragma once
// Small helpers shared by the unit and validation tests. Nothing here computes
// an expected value from the solver itself: references are closed forms
// written out in each test.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <string>
#include <vector>

#include "xpbd/distance_stream.hpp"
#include "xpbd/xpbd.hpp"

namespace xpbd::test {

inline constexpr Real kEps = std::numeric_limits<Real>::epsilon();

// Runs compile() and checks that it throws SceneError (and nothing else) with
// a message containing every string of `parts` (element index, field, value).
inline ::testing::AssertionResult scene_error_names(const SceneDesc& scene,
                                                    std::initializer_list<std::string> parts) {
  try {
    (void)compile(scene);
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    for (const std::string& p : parts)
      if (msg.find(p) == std::string::npos)
        return ::testing::AssertionFailure() << "message \"" << msg << "\" does not contain \"" << p
                                             << "\"";
    return ::testing::AssertionSuccess() << msg;
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "threw a non-SceneError: " << e.what();
  }
  return ::testing::AssertionFailure() << "compile() accepted the scene";
}

// Same for step(): must throw ConfigError naming every string of `parts`.
inline ::testing::AssertionResult config_error_names(const Model& m, State& s, const StepConfig& cfg,
                                                     std::initializer_list<std::string> parts) {
  try {
    step(m, s, cfg);
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    for (const std::string& p : parts)
      if (msg.find(p) == std::string::npos)
        return ::testing::AssertionFailure() << "message \"" << msg << "\" does not contain \"" << p
                                             << "\"";
    return ::testing::AssertionSuccess() << msg;
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "threw a non-ConfigError: " << e.what();
  }
  return ::testing::AssertionFailure() << "step() accepted the config";
}

// Runs f; it must throw E (and nothing else) with every string of `parts` in
// its message.
template <class E, class F>
::testing::AssertionResult throws_naming(F&& f, std::initializer_list<std::string> parts) {
  try {
    f();
  } catch (const E& e) {
    const std::string msg = e.what();
    for (const std::string& p : parts)
      if (msg.find(p) == std::string::npos)
        return ::testing::AssertionFailure() << "message \"" << msg << "\" lacks \"" << p << "\"";
    return ::testing::AssertionSuccess() << msg;
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "threw another exception: " << e.what();
  }
  return ::testing::AssertionFailure() << "did not throw";
}

// Sum of a scene's particle masses (kg).
inline Real total_mass(const SceneDesc& s) {
  Real m = 0;
  for (Real x : s.masses) m += x;
  return m;
}

inline bool all_finite(const std::vector<Vec3>& v) {
  for (const Vec3& x : v)
    if (!x.allFinite()) return false;
  return true;
}

inline bool all_finite(const State& s) {
  if (!all_finite(s.x) || !all_finite(s.v) || !all_finite(s.x_prev)) return false;
  for (const auto& l : s.lambda)
    for (Real v : l)
      if (!std::isfinite(v)) return false;
  return true;
}

// A 1-D spring along +x: particle 0 is a kinematic anchor (mass 0) at the
// origin, particle 1 (mass m, kg) starts at (rest + u0, 0, 0) with velocity
// (v0, 0, 0). One distance constraint of rest length `rest` (m) and material
// `mat`. With zero gravity the motion stays on the x axis exactly (the
// gradient has zero y and z components), so the constraint is linear in the
// free coordinate and a single XPBD projection solves it exactly.
struct Spring1D {
  Real m = 1, rest = 1, u0 = Real(0.5), v0 = 0;
  Material mat;
};

inline SceneDesc spring_scene(const Spring1D& sp) {
  SceneDesc s;
  s.add_particle(Vec3::Zero(), 0);
  s.add_particle(Vec3(sp.rest + sp.u0, 0, 0), sp.m, 0, Vec3(sp.v0, 0, 0));
  s.distances.push_back(DistanceDesc{0, 1, sp.rest, sp.mat});
  return s;
}

// Times (s) at which the samples (t_i, y_i) cross zero in the given direction
// (+1 upward, -1 downward), by linear interpolation between samples.
inline std::vector<double> zero_crossings(const std::vector<double>& t, const std::vector<double>& y,
                                          int direction) {
  std::vector<double> out;
  for (std::size_t i = 1; i < y.size(); ++i) {
    const bool up = y[i - 1] < 0 && y[i] >= 0;
    const bool down = y[i - 1] > 0 && y[i] <= 0;
    if ((direction > 0 && up) || (direction < 0 && down)) {
      const double s = y[i - 1] / (y[i - 1] - y[i]);
      out.push_back(t[i - 1] + s * (t[i] - t[i - 1]));
    }
  }
  return out;
}

// Mean period from same-direction zero crossings: (last - first) / count.
inline double mean_period(const std::vector<double>& crossings) {
  if (crossings.size() < 2) return std::nan("");
  return (crossings.back() - crossings.front()) / double(crossings.size() - 1);
}

// The vector kernels of the coloured sweeps that this build has on this
// CPU, widest first: "avx512", "avx512-ymm" (the Distance sweep's 256-bit
// AVX-512 kernel, where the CPU reports AVX-512VL), "avx2", or none.
inline std::vector<std::string> vector_kernels() {
  const std::string widest = simd_kernel();
  if (widest == "avx2") return {"avx2"};
  if (widest != "avx512") return {};
  std::vector<std::string> k{"avx512"};
  try {
    set_simd_kernel("avx512-ymm");
    k.push_back("avx512-ymm");
  } catch (const ConfigError&) {
    // no AVX-512VL
  }
  set_simd_kernel("auto");
  k.push_back("avx2");
  return k;
}

// Runs the coloured sweeps on kernel `name` (set_simd_kernel; the Distance
// sweep's too, not its measured choice) while it lives; then the default
// again ("auto").
class KernelCap {
 public:
  explicit KernelCap(const std::string& name) { set_simd_kernel(name); }
  ~KernelCap() { set_simd_kernel("auto"); }
  KernelCap(const KernelCap&) = delete;
  KernelCap& operator=(const KernelCap&) = delete;
};

}  // namespace xpbd::test
