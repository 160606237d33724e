// The Distance stream kernel (stream_kernel.hpp) at AVX2's width, 8 floats
// or 4 doubles per register (avx2_lane.hpp), built with AVX-512VL
// (-mavx512f -mavx512vl, and -ffp-contract=off: no FMA): comparisons give
// mask registers, and the compiler has 32 vector registers, where the
// AVX2 kernel spills to the stack with 16. stream.cpp calls it only on a
// CPU that reports AVX-512F and AVX-512VL. The same bits as every other
// Distance kernel.
#include "avx2_lane.hpp"
#include "stream_kernel.hpp"

namespace xpbd::detail {

void project_stream_avx512_ymm(const StreamArgs& s, std::size_t lo, std::size_t hi, bool damped, bool first) {
  project_stream_variant<Avx2Lane>(s, lo, hi, damped, first);
}

}  // namespace xpbd::detail
