#include "xpbd/builders.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "xpbd/error.hpp"

namespace xpbd {

ClothGrid add_cloth_grid(SceneDesc& s, const ClothGridDesc& d) {
  if (d.nx < 2 || d.ny < 2)
    throw SceneError("cloth.nx/ny: need at least 2 x 2 particles, got " + std::to_string(d.nx) +
                     " x " + std::to_string(d.ny));
  ClothGrid g{s.num_particles(), d.nx, d.ny};
  auto is_pinned = [&](int i, int j) {
    return std::find(d.pinned.begin(), d.pinned.end(), std::make_pair(i, j)) != d.pinned.end();
  };
  for (const auto& [i, j] : d.pinned)
    if (i < 0 || i >= d.nx || j < 0 || j >= d.ny)
      throw SceneError("cloth.pinned: (" + std::to_string(i) + ", " + std::to_string(j) +
                       ") is outside the " + std::to_string(d.nx) + " x " + std::to_string(d.ny) +
                       " grid");
  int movable = 0;
  for (int j = 0; j < d.ny; ++j)
    for (int i = 0; i < d.nx; ++i) movable += is_pinned(i, j) ? 0 : 1;
  const Real m = movable > 0 ? d.mass / Real(movable) : Real(0);
  const Real du = d.size_u / Real(d.nx - 1), dv = d.size_v / Real(d.ny - 1);
  for (int j = 0; j < d.ny; ++j)
    for (int i = 0; i < d.nx; ++i) {
      const bool pin = is_pinned(i, j);
      const Index k = s.add_particle(d.origin + (Real(i) * du) * d.u + (Real(j) * dv) * d.v,
                                     pin ? Real(0) : m, d.radius);
      if (pin) s.pins.push_back(PinDesc{k, std::nullopt, Material{}});
    }
  auto edge = [&](int i0, int j0, int i1, int j1, const Material& mat) {
    s.distances.push_back(DistanceDesc{g.at(i0, j0), g.at(i1, j1), std::nullopt, mat});
  };
  for (int j = 0; j < d.ny; ++j)
    for (int i = 0; i < d.nx; ++i) {
      if (i + 1 < d.nx) edge(i, j, i + 1, j, d.stretch);
      if (j + 1 < d.ny) edge(i, j, i, j + 1, d.stretch);
    }
  if (d.shear)
    for (int j = 0; j + 1 < d.ny; ++j)
      for (int i = 0; i + 1 < d.nx; ++i) {
        edge(i, j, i + 1, j + 1, d.shear_mat);
        edge(i + 1, j, i, j + 1, d.shear_mat);
      }
  if (d.bend_distance)
    for (int j = 0; j < d.ny; ++j)
      for (int i = 0; i < d.nx; ++i) {
        if (i + 2 < d.nx) edge(i, j, i + 2, j, d.bend_mat);
        if (j + 2 < d.ny) edge(i, j, i, j + 2, d.bend_mat);
      }
  return g;
}

Index add_rope(SceneDesc& s, const RopeDesc& d) {
  if (d.n < 2) throw SceneError("rope.n: need at least 2 particles, got " + std::to_string(d.n));
  if (!(d.spacing > Real(0)))
    throw SceneError("rope.spacing: must be > 0, got " + std::to_string(d.spacing));
  const Index first = s.num_particles();
  for (int k = 0; k < d.n; ++k) {
    const bool pin = d.pin_first && k == 0;
    const Index i = s.add_particle(d.start + (Real(k) * d.spacing) * d.dir, pin ? Real(0) : d.mass,
                                   d.radius);
    if (pin) s.pins.push_back(PinDesc{i, std::nullopt, Material{}});
    if (k > 0) s.distances.push_back(DistanceDesc{i - 1, i, d.spacing, d.mat});
  }
  return first;
}

}  // namespace xpbd
