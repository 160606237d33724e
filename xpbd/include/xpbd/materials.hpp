#pragma once
// Changing the material (compliance, damping, PBD stiffness) of constraint
// elements of a compiled Model, between steps: what a game or a tool does
// when a cloth gets wet or a rope is tightened, without recompiling the
// scene. The elements, particles and everything else stay as they are.
#include <cstddef>

#include "xpbd/constraint_types.hpp"
#include "xpbd/model.hpp"
#include "xpbd/profile.hpp"

namespace xpbd {

namespace detail {
// Throws ConfigError naming the type, the range and the bad field or value.
void check_material_change(const char* type, std::size_t first, std::size_t count, std::size_t size,
                           const Material& mat);
// Copies the Distance elements into Model::distance_by_colour again.
void refresh_distance_colours(Model& m);
// Builds Model::dihedral_stream again from the DihedralBending elements.
void refresh_dihedral_stream(Model& m);
// Builds Model::tether_stream again from the Tether elements.
void refresh_tether_stream(Model& m);
}  // namespace detail

// Sets the material of elements [first, first + count) of constraint type T
// (in the order of model.get<T>()) to `mat`. Throws ConfigError, leaving the
// model unchanged, if the range is outside the elements or the material is
// invalid (compliance and damping finite and >= 0, stiffness in [0, 1]).
// The new material takes effect at the next step. The multipliers of the
// current step are reset at every substep, so nothing else needs updating.
template <class T>
void set_material(Model& m, std::size_t first, std::size_t count, const Material& mat) {
  std::vector<T>& es = m.get<T>();
  detail::check_material_change(kStageNames[stage::of<T>], first, count, es.size(), mat);
  for (std::size_t k = first; k < first + count; ++k) es[k].mat = mat;
  bool any = false;
  for (const T& c : es) any = any || c.mat.damping != Real(0);
  m.has_damping[type_index_v<T>] = any;
  if constexpr (std::is_same_v<T, Distance>) detail::refresh_distance_colours(m);
  if constexpr (std::is_same_v<T, DihedralBending>) detail::refresh_dihedral_stream(m);
  if constexpr (std::is_same_v<T, Tether>) detail::refresh_tether_stream(m);
}

// All elements of type T.
template <class T>
void set_material(Model& m, const Material& mat) {
  set_material<T>(m, 0, m.get<T>().size(), mat);
}

}  // namespace xpbd
