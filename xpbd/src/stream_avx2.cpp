// The AVX2 stream kernels (stream_kernel.hpp, tether_kernel.hpp,
// dihedral_kernel.hpp) over avx2_lane.hpp's lanes: 8 floats or 4 doubles
// per register. This file alone is built with -mavx2 (and
// -ffp-contract=off, no FMA); stream.cpp calls it only on a CPU that
// reports AVX2.
#include "avx2_lane.hpp"
#include "dihedral_kernel.hpp"
#include "stream_kernel.hpp"
#include "tether_kernel.hpp"

namespace xpbd::detail {

void project_stream_avx2(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first) {
  project_stream_variant<Avx2Lane>(s, lo, hi, damped, first);
}

void project_tether_avx2(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first) {
  project_tether_variant<Avx2Lane>(s, lo, hi, damped, first);
}

void project_dihedral_avx2(const DihedralArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first) {
  project_dihedral_variant<Avx2Lane>(s, lo, hi, damped, first);
}

}  // namespace xpbd::detail
