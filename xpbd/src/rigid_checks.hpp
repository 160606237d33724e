#pragma once
// The checks step() runs on the rigid-body input of a State (bodies,
// particle contacts, attachments, and the indices of the other contact
// kinds) before it solves anything. Internal to xpbd. Each throws
// ConfigError naming the list, the element, the field and the value.
#include <cstddef>

#include "xpbd/model.hpp"
#include "xpbd/state.hpp"

namespace xpbd::rigid::detail {

// Bodies from index `from` on: finite pose, velocities and accelerations,
// inverse mass and inertia finite and >= 0.
void check_bodies(const State& s, std::size_t from);

// Element k of list `what` ("contacts", "attachments", ...): its particle
// index in range, its body index < the number of bodies (-1: the world).
void check_index(const Model& m, const State& s, const char* what, std::size_t k, Index p, Index b);

// Particle contact k: indices as above; r finite, n a finite unit vector
// (within 1e-3), thickness and compliance finite and >= 0, friction and
// restitution finite (<= 0: none).
void check_contact(const Model& m, const State& s, std::size_t k);

// Attachment k: indices as above; r finite, compliance finite and >= 0.
void check_attachment(const Model& m, const State& s, std::size_t k);

// Feature-triangle contact k: indices; r finite, side +1 or -1, thickness
// finite and >= 0, friction finite, reach >= 0 (or infinity), closing_speed
// finite and >= 0.
void check_triangle_contact(const Model& m, const State& s, std::size_t k);

// Edge-edge contact k: indices; a, b finite, out a unit vector, thickness
// and closing_speed finite and >= 0, reach >= 0 (or infinity).
void check_edge_contact(const Model& m, const State& s, std::size_t k);

// Body-world contact k: body in range, other in range (-1: the static
// world) and not the body; r, p, n finite, n of unit length, friction
// finite and >= 0.
void check_world_contact(const State& s, std::size_t k);

}  // namespace xpbd::rigid::detail
