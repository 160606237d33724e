#include "demos/state_hash.hpp"

#include <cstring>

namespace xpbd_demos {

namespace {

constexpr std::uint64_t kOffset = 14695981039346656037ull, kPrime = 1099511628211ull;

void mix(std::uint64_t& h, xpbd::Real value) {
  unsigned char bytes[sizeof value];
  std::memcpy(bytes, &value, sizeof value);
  for (unsigned char b : bytes) {
    h ^= b;
    h *= kPrime;
  }
}

}  // namespace

std::uint64_t state_hash(std::span<const xpbd::Vec3> x, std::span<const xpbd::Vec3> v,
                         std::span<const BodyPose> bodies) {
  std::uint64_t h = kOffset;
  for (const auto* part : {&x, &v})
    for (const xpbd::Vec3& p : *part)
      for (int c = 0; c < 3; ++c) mix(h, p[c]);
  for (const BodyPose& b : bodies) {
    for (int c = 0; c < 3; ++c) mix(h, b.position[c]);
    for (xpbd::Real q : b.orientation) mix(h, q);
  }
  return h;
}

}  // namespace xpbd_demos
