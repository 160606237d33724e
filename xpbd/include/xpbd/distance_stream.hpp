#pragma once
// The compiled form of the coloured Distance sweep (StepConfig::coloured,
// XPBD): what the kernel reads per element and nothing else, in the order
// of Model::distance_colours, as parallel arrays (structure of arrays), so
// that a vector kernel loads the data of 4 or 8 consecutive elements of a
// colour with one instruction each. A Distance element is 40 bytes in
// double (its whole Material); its stream entry is 32 (two particle
// indices, rest length, compliance, damping), and the kernel reads the
// damping only when some element has it.
//
// The particles the kernel reads are records (x, y, z, 1/m) in
// State::stream_x, copied from State::x before the Distance stage of a
// sweep and back after it; the multipliers are in State::stream_lambda, in
// stream order, copied to State::lambda at the end of every step. What does
// not change within a step (compliance/h^2, the inverse of each element's
// denominator, compliance*damping/h) is computed at the start of a step, so
// a sweep divides only once per element (1/|d|^2, beside the square root),
// and kept for the next step when its substep h, the stream and the damping
// switch are the same (DistanceStream::serial, State::StreamFactors).
//
// step() runs the widest kernel this CPU has (simd_kernel()): where the
// library was built for x86-64, AVX-512 (16 floats or 8 doubles at a time)
// when the CPU reports AVX-512F, else AVX2 when it reports AVX2; the
// scalar kernel otherwise (or with StepConfig::simd = false). The Distance
// sweep is the exception (distance_kernel()): where the CPU has AVX-512,
// it runs whichever of its vector kernels swept a test colour fastest on
// this CPU, timed once per process at its first sweep: AVX2, AVX-512 at
// AVX2's width (8 floats or 4 doubles, with AVX-512VL's mask registers and
// 32 vector registers; "avx512-ymm"), and in double AVX-512 at 512 bits
// (1.3-1.5 times AVX2 on an Intel Xeon; on an AMD EPYC 0.8 times, where
// the 256-bit one was the fastest). All do the
// same floating-point operations in the same order on every element,
// without fused multiply-adds, so they give the same results bit for bit
// (tests/unit/test_distance_stream.cpp).
#include <cstdint>
#include <string>
#include <vector>

#include "xpbd/types.hpp"

namespace xpbd {

struct Model;
struct State;
struct SolveContext;
class Workers;

// Also the compiled form of the Tether elements (Model::tether_stream, in
// the order of Model::tether_colours): a is the tethered particle, b its
// anchor, rest the tether's length. Their kernel is the one-sided update of
// a tether (tether_kernel.hpp), over the same records.
struct DistanceStream {
  std::vector<Index> a, b;        // particles of element order[j]
  std::vector<Real> rest;         // m
  std::vector<Real> compliance;   // m/N
  std::vector<Real> damping;      // s (Material::damping)
  // 1/kg: inv_mass[a] + inv_mass[b] (Model::inv_mass is fixed after
  // compile), so that the per-step factors need no gather.
  std::vector<Real> inv_mass_sum;
  // Stamped by compile() (and set_material) with a number no other stream
  // of this process has, and kept by a copy. A state keeps the per-step
  // factors it computed for a stream, and computes them again only when the
  // substep, the damping switch or this number differs (State::StreamFactors),
  // so a stream must not be changed in place once stepped: compile it again.
  // 0: never kept.
  std::uint64_t serial = 0;

  std::size_t size() const { return a.size(); }
};

// One sweep of m's Distance elements over the stream, colour by colour
// (last to first for sc.reverse), as step() runs it with coloured XPBD:
// the widest kernel if `simd`, else the scalar one; over `workers` when
// given. prepare_stream must have been called for this model, state and
// substep h (step() does at the start of every step); it also zeroes the
// multipliers, s.stream_lambda[j] for element m.distance_colours.order[j].
// prepare_stream prepares the DihedralBending stream (dihedral_stream.hpp)
// as well.
// The Tether stream is prepared (its multipliers zeroed) too, and
// project_tether_stream is the same sweep over it.
// Throws ConfigError if the state is not prepared, or h is not > 0.
void prepare_stream(const Model& m, State& s, Real h, Workers* workers = nullptr);
void project_stream(const Model& m, State& s, const SolveContext& sc, bool simd,
                    Workers* workers = nullptr);
void project_tether_stream(const Model& m, State& s, const SolveContext& sc, bool simd,
                           Workers* workers = nullptr);

// "avx512", "avx2" or "scalar": the widest kernel step() runs for the
// coloured XPBD sweeps with StepConfig::simd on, on this CPU with this
// build (and at most the one set_simd_kernel allows; see above for the
// float Distance sweep).
const char* simd_kernel();

// "avx512", "avx512-ymm", "avx2" or "scalar": the kernel step() runs for
// the coloured XPBD Distance sweep with StepConfig::simd on (see above;
// the one set_simd_kernel names, if it named one). The first call may time
// the vector kernels (about a millisecond), if no sweep has yet. With
// `levels`: the kernel of the array order's sweep over its levels
// (StepConfig::levels), timed on short runs, the levels' shape, since the
// 512-bit kernel leaves more of each short run to its scalar tail.
const char* distance_kernel(bool levels = false);

// Caps the kernel of the coloured sweeps for the whole process at `name`
// ("avx512", "avx2" or "scalar"), the Distance sweep's included: a named
// kernel is run, not measured against another ("avx512" runs the 512-bit
// Distance kernel in double, and the 256-bit AVX-512 one in float, which
// has no 512-bit one). "avx512-ymm" is "avx512" with the Distance sweep on
// its 256-bit AVX-512 kernel. "auto" is the start: no cap, the widest
// kernel there is, and the Distance sweep's measured choice (see above).
// Every kernel gives the same bits, so this changes speed only: it exists
// to measure the kernels against each other in one run. Throws
// ConfigError, naming the value, for another name or for a kernel this
// build or CPU does not have.
void set_simd_kernel(const std::string& name);

}  // namespace xpbd
