#include "demos/scene_hanging_cloth.hpp"

namespace xpbd_demos {

HangingCloth make_hanging_cloth(const HangingClothParams& p) {
  using xpbd::Real;
  HangingCloth c;
  xpbd::ClothGridDesc d;
  d.nx = p.n;
  d.ny = p.n;
  d.size_u = p.size;
  d.size_v = p.size;
  d.origin = xpbd::Vec3(-p.size / 2, c.pin_height, 0);
  d.u = xpbd::Vec3::UnitX();  // along the pinned edge
  d.v = xpbd::Vec3::UnitZ();  // horizontal: the cloth starts flat
  d.mass = p.mass;
  const xpbd::Material mat{p.compliance, Real(0), p.pbd_stiffness};
  d.stretch = mat;
  d.shear = true;
  d.shear_mat = mat;
  d.bend_distance = true;
  d.bend_mat = mat;
  d.pinned = {{0, 0}, {p.n - 1, 0}};
  c.grid = xpbd::add_cloth_grid(c.scene, d);
  return c;
}

}  // namespace xpbd_demos
