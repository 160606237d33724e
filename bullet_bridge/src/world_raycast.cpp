// XpbdWorld's ray queries (world.hpp): xpbd::ray_hits over every system.
#include <algorithm>
#include <string>
#include <utility>

#include "world_impl.hpp"
#include "xpbd/error.hpp"

namespace xpbd_bullet {

std::vector<XpbdWorld::RayHit> XpbdWorld::ray_test_all(const btVector3& from, const btVector3& to) const {
  const Vec3 a = to_vec(from), b = to_vec(to);
  for (const auto& [name, v] : {std::pair{"from", a}, std::pair{"to", b}})
    if (!v.allFinite())
      throw xpbd::ConfigError(std::string("ray_test: ") + name + " must be finite, got (" +
                              xpbd::format_value(double(v.x())) + ", " + xpbd::format_value(double(v.y())) +
                              ", " + xpbd::format_value(double(v.z())) + ")");
  std::vector<RayHit> hits;
  for (const auto& s : systems_) {
    if (!s->error.empty()) continue;
    for (const xpbd::RayHit& h : xpbd::ray_hits(*s->model, s->state, a, b)) hits.push_back(RayHit{SystemId(s->id), h});
  }
  std::stable_sort(hits.begin(), hits.end(), [](const RayHit& x, const RayHit& y) {
    return x.hit.fraction != y.hit.fraction ? x.hit.fraction < y.hit.fraction : x.system < y.system;
  });
  return hits;
}

std::optional<XpbdWorld::RayHit> XpbdWorld::ray_test_closest(const btVector3& from, const btVector3& to) const {
  std::vector<RayHit> hits = ray_test_all(from, to);
  if (hits.empty()) return std::nullopt;
  return hits.front();
}

}  // namespace xpbd_bullet
