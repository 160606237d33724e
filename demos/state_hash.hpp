#pragma once
// A hash of a run's state, bit for bit (xpbd-demo --hash; docs/reliability.md).
#include <cstdint>
#include <span>

#include "demos/rigid_world.hpp"
#include "xpbd/types.hpp"

namespace xpbd_demos {

// 64-bit FNV-1a over the bytes of every particle position and velocity and
// every body's position and orientation, in order, in the build's scalar
// type (a float build hashes floats). Equal states give equal hashes in any
// process; a change of one bit in any value changes the hash (up to 64-bit
// collisions). -0.0 and 0.0 differ, as do NaNs with different payloads.
std::uint64_t state_hash(std::span<const xpbd::Vec3> x, std::span<const xpbd::Vec3> v,
                         std::span<const BodyPose> bodies);

}  // namespace xpbd_demos
