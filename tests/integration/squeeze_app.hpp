#pragma once
// The bar-squeeze application of test_world_squeeze.cpp, shared with the
// campaign program squeeze_campaign.cpp (scripts/squeeze_seeds.sh): a
// ground plane, a 2 kg bar with a 24 x 24 cloth of 0.4 kg hanging from it by
// three attachments, and 0 or 49 random rigid bodies falling around it; 600
// frames at 60 Hz, measured every frame.
#include <functional>
#include <vector>

#include "support.hpp"

namespace xpbd_bullet::test::squeeze {

using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

inline constexpr int kFrames = 600;
inline constexpr int kN = 24;                  // particles per side
inline constexpr Real kClothMass = Real(0.4);  // kg
inline constexpr Real kBarMass = 2;            // kg
inline const Vec3 kBarHalf(0.6, 0.03, 0.03);   // m
inline const Vec3 kBarStart(0, 1.6, 0);        // m
inline constexpr Real kWrinkle = Real(0.001);  // m, see add_cloth
// The cloth's particles attached to the bar (the cloth is the system's only
// particles, so these are also their indices in the system).
inline constexpr int kAttached[3] = {0, kN / 2, kN - 1};

struct Result {
  Real deepest = 0;     // m, largest depth of a particle centre inside a body or below the ground
  Real strain = 0;      // largest (|x_a - x_b| - rest) / rest over the cloth's distance edges
  // Frames whose deepest particle centre is deeper than the thickness, and
  // of those, the frames where that particle is also within 1 cm of a
  // second body (squeezed between two).
  int frames_deep = 0;
  int frames_squeezed = 0;
  std::vector<Vec3> bar;  // the bar's centre at every frame
  bool finite = true;
  // The health check found the energy out of bounds after the first frame,
  // or a non-finite state, in some frame. (In the first frame the cloth's
  // top row starts on the bar's face, inside the contact band, and is
  // pushed out within the first substep: at 200 substeps that alone is
  // over the check's budget, 0.40 J against 0.013 J for wrinkle seed 2.)
  bool exploded = false;
  double sweeps_per_step = 0;  // mean Gauss-Seidel sweeps per Bullet step
  // Frames with an edge stretched over 20 %; such edges summed over the
  // frames, and those of them whose midpoint is inside a body.
  int frames_over = 0;
  long edges_over = 0, edges_through = 0;
  // Of edges_through: those through the bar, and those with an end at a
  // particle attached to the bar.
  long edges_through_bar = 0, edges_through_attached = 0;
};

// `bodies` random rigid bodies around the bar, from a fixed seed, each
// placed clear of the cloth, the bar and the bodies placed before it: its
// bounding sphere (radius 1.8 `size` for every shape below) is drawn again
// until it keeps 1 cm from the box around the bar and the hanging cloth and
// from the others' spheres. Until 2026-11-28 the centres were drawn with no
// such check, and bodies began through the cloth: in frame 0 a 0.19 kg
// capsule lay across a cloth edge, whose particles the contacts held on its
// two sides; the capsule fell carrying the edge, stretched by 1.3-1.6, for
// 60 frames, the largest strain of the run (wrinkle seed 1). A body that
// starts through the cloth is on neither side of it, and no contact can
// tell which side it belongs on.
void add_random_bodies(BulletWorld& bw, int bodies, unsigned seed = 12345);

// The 24 x 24 cloth with its top edge along the bar's bottom face, added to
// xw with `set` and attached to the bar at three particles. Each particle
// is set off its plane by up to kWrinkle (a fixed seed): a cloth is never
// flat to the millimetre. An exactly flat one stays exactly in its plane
// (every out-of-plane coordinate is 0 and stays 0 here), where its
// distance edges make a rigid truss: the bar landed on it and stood on it,
// 1 m above the ground, to the last frame, and never squeezed it.
// triangles: the cloth's faces collide with the bar's corners and edges
// (ClothGridDesc::collision_triangles). wrinkle_seed: the offsets' seed.
// bend, shear: the compliances (m/N) of the bending and shear distance
// edges; 0, the application's, makes every edge rigid (squeeze_rest.cpp
// measures softer ones).
xpbd_bullet::SystemId add_cloth(XpbdWorld& xw, btRigidBody* bar, const SystemSettings& set, bool triangles = false,
                                unsigned wrinkle_seed = 1, Real bend = 0, Real shear = 0);

// after_solve = false turns off what answers Bullet's own contacts moving
// the bodies after XPBD ran (ContactSettings::settle and spacers).
// substeps: 0 for the default; wrinkle_seed: add_cloth's; penetration:
// the tolerance's contact target (SystemSettings::tolerance, m, 0 = off:
// the fixed budget); wedges: ContactSettings::wedges; surface_edges:
// ContactSettings::surface_edge_contacts; strain: the tolerance's strain
// target (SystemSettings::tolerance.strain, 0 = off); tweak: called on
// the system's settings last, for any other setting (the campaign's flags);
// bend, shear: add_cloth's compliances.
Result run(int bodies, bool cloth, int contact_sweeps = 0, bool after_solve = true, int substeps = 0,
           unsigned wrinkle_seed = 1, int frames = kFrames,
           double penetration = SystemSettings{}.tolerance.penetration, bool wedges = true,
           bool surface_edges = xpbd_bullet::ContactSettings{}.surface_edge_contacts,
           double strain = SystemSettings{}.tolerance.strain,
           const std::function<void(SystemSettings&)>& tweak = {}, Real bend = 0, Real shear = 0);

}  // namespace xpbd_bullet::test::squeeze
