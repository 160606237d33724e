#include "xpbd/materials.hpp"

#include <charconv>
#include <cmath>
#include <string>

#include "xpbd/error.hpp"
#include "stream.hpp"

namespace xpbd::detail {
namespace {
std::string num(Real v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}
}  // namespace

void check_material_change(const char* type, std::size_t first, std::size_t count, std::size_t size,
                           const Material& mat) {
  const std::string where = std::string("set_material<") + type + ">";
  if (first > size || count > size - first)
    throw ConfigError(where + ": elements [" + std::to_string(first) + ", " + std::to_string(first) + " + " +
                      std::to_string(count) + ") outside the " + std::to_string(size) + " elements");
  if (!(mat.compliance >= Real(0)) || !std::isfinite(mat.compliance))
    throw ConfigError(where + ": mat.compliance must be finite and >= 0, got " + num(mat.compliance));
  if (!(mat.damping >= Real(0)) || !std::isfinite(mat.damping))
    throw ConfigError(where + ": mat.damping must be finite and >= 0, got " + num(mat.damping));
  if (!(mat.stiffness >= Real(0) && mat.stiffness <= Real(1)))
    throw ConfigError(where + ": mat.stiffness must be in [0, 1], got " + num(mat.stiffness));
}

void refresh_distance_colours(Model& m) {
  const auto& d = m.get<Distance>();
  const auto& order = m.distance_colours.order;
  if (m.distance_by_colour.size() != order.size()) return;  // no schedule (not from compile)
  for (std::size_t j = 0; j < order.size(); ++j)
    m.distance_by_colour[j] = d[static_cast<std::size_t>(order[j])];
  m.distance_stream = make_distance_stream(m);
  if (m.distance_levels.order.size() == d.size()) m.distance_level_stream = make_distance_level_stream(m);
}

void refresh_dihedral_stream(Model& m) {
  if (m.dihedral_colours.order.size() != m.get<DihedralBending>().size()) return;  // no schedule
  m.dihedral_stream = make_dihedral_stream(m);
}

void refresh_tether_stream(Model& m) {
  if (m.tether_colours.order.size() != m.get<Tether>().size()) return;  // no schedule
  m.tether_stream = make_tether_stream(m);
  if (m.tether_levels.order.size() == m.get<Tether>().size()) m.tether_level_stream = make_tether_level_stream(m);
}

}  // namespace xpbd::detail
