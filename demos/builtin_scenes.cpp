#include "demos/builtin_scenes.hpp"

#include <cmath>
#include <map>
#include <numbers>
#include <utility>

namespace xpbd_demos {
namespace {

using xpbd::Index;
using xpbd::Material;
using xpbd::Real;
using xpbd::Vec3;

constexpr Real kPi = std::numbers::pi_v<Real>;

// Unit quaternion (w, x, y, z) of a rotation by `angle` (rad) about `axis`.
std::array<Real, 4> rotation(const Vec3& axis, Real angle) {
  const Vec3 a = axis.normalized() * std::sin(angle / 2);
  return {std::cos(angle / 2), a.x(), a.y(), a.z()};
}

RigidSpec ground(Real y = 0, Real friction = Real(0.5)) {
  RigidSpec g;
  g.name = "ground";
  g.shape.kind = ShapeKind::plane;
  g.shape.normal = Vec3::UnitY();
  g.shape.offset = y;
  g.friction = friction;
  return g;
}

RigidSpec sphere(const std::string& name, Real radius, const Vec3& at, Real mass) {
  RigidSpec b;
  b.name = name;
  b.shape.kind = ShapeKind::sphere;
  b.shape.radius = radius;
  b.position = at;
  b.mass = mass;
  return b;
}

RigidSpec box(const std::string& name, const Vec3& half, const Vec3& at, Real mass) {
  RigidSpec b;
  b.name = name;
  b.shape.kind = ShapeKind::box;
  b.shape.half_extents = half;
  b.position = at;
  b.mass = mass;
  return b;
}

// A horizontal square cloth of n x n particles, side `size` (m), centred
// over (cx, cz) at height y; edges structural + shear + bending distance,
// all with compliance `alpha` (m/N).
xpbd::ClothGridDesc flat_cloth(int n, Real size, const Vec3& centre, Real mass, Real alpha) {
  xpbd::ClothGridDesc d;
  d.nx = d.ny = n;
  d.size_u = d.size_v = size;
  d.origin = centre - Vec3(size / 2, 0, size / 2);
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  d.mass = mass;
  d.stretch = d.shear_mat = d.bend_mat = Material{alpha, 0, 1};
  return d;
}

// ---------------------------------------------------------------------------

SceneSpec hanging_cloth() {
  // The seed report's Fig. 5 setup: 32 x 32, 1 m, 1 kg, starting flat,
  // pinned at the two corners of one edge, every edge (structural, shear,
  // bending distance) 1e-8 m/N. No rigid bodies.
  SceneSpec s;
  s.name = "hanging_cloth";
  s.description = "32x32 cloth pinned at two corners swings down under gravity (the seed's Fig. 5)";
  xpbd::ClothGridDesc d = flat_cloth(32, 1, Vec3(0, 0, Real(0.5)), 1, Real(1e-8));
  d.pinned = {{0, 0}, {31, 0}};
  s.soft.generators.push_back(d);
  s.solver.frames = 180;
  return s;
}

SceneSpec cloth_on_sphere() {
  // A 1 m cloth dropped onto a static sphere next to a light dynamic box
  // lying on the ground: contacts with a static and a dynamic body,
  // friction, and two-way coupling (the box gets pushed).
  SceneSpec s;
  s.name = "cloth_on_sphere";
  s.description = "32x32 cloth drops onto a static sphere and a light dynamic box on the ground";
  xpbd::ClothGridDesc d = flat_cloth(32, Real(1.2), Vec3(Real(0.1), Real(0.8), 0), Real(0.3), Real(1e-6));
  s.soft.generators.push_back(d);
  s.soft.contacts.thickness = Real(0.01);
  s.bodies.push_back(ground());
  s.bodies.push_back(sphere("sphere", Real(0.25), Vec3(0, Real(0.35), 0), 0));
  s.bodies.push_back(box("box", Vec3(Real(0.1), Real(0.1), Real(0.1)), Vec3(Real(0.45), Real(0.1), 0), Real(0.2)));
  s.solver.frames = 180;
  return s;
}

SceneSpec cloth_on_box_corner() {
  // A coarse cloth onto a box standing on a corner: the corner falls between
  // particles, so only the rigid-feature-vs-triangle penetration
  // constraint (collision_triangles) keeps it from poking through.
  SceneSpec s;
  s.name = "cloth_on_box_corner";
  s.description = "coarse 12x12 cloth onto the upward corner of a static box (feature-vs-triangle contacts)";
  xpbd::ClothGridDesc d = flat_cloth(12, 1, Vec3(Real(0.02), Real(0.55), Real(0.03)), Real(0.2), Real(1e-6));
  d.collision_triangles = true;
  s.soft.generators.push_back(d);
  s.soft.contacts.thickness = Real(0.005);
  s.soft.contacts.static_friction = s.soft.contacts.dynamic_friction = Real(0.8);
  // Body diagonal (1, 1, 1) turned onto +y: a corner points straight up.
  RigidSpec b = box("box", Vec3::Constant(Real(0.15)), Vec3(0, Real(0.15) * std::sqrt(Real(3)), 0), 0);
  const Vec3 diag = Vec3::Ones().normalized();
  b.orientation = rotation(diag.cross(Vec3::UnitY()), std::acos(diag.y()));
  s.bodies.push_back(ground());
  s.bodies.push_back(b);
  s.solver.frames = 150;
  return s;
}

SceneSpec flag() {
  // A banner on a horizontal pole: pinned along the edge next to the pole,
  // it starts horizontal and swings down around the pole; dihedral bending
  // keeps it from creasing sharply.
  SceneSpec s;
  s.name = "flag";
  s.description = "24x16 banner pinned along one edge next to a pole swings down (dihedral bending)";
  xpbd::ClothGridDesc d;
  d.nx = 24;
  d.ny = 16;
  d.size_u = Real(1.2);
  d.size_v = Real(0.8);
  d.origin = Vec3(Real(0.03), Real(1.6), Real(-0.4));
  d.u = Vec3::UnitX();  // away from the pole
  d.v = Vec3::UnitZ();  // along the pole: the pinned edge is i = 0
  d.mass = Real(0.2);
  d.stretch = d.shear_mat = Material{Real(1e-7), 0, 1};
  d.set_bending(xpbd::ClothBending::dihedral, Material{Real(5), 0, 1});
  for (int j = 0; j < d.ny; ++j) d.pinned.emplace_back(0, j);
  s.soft.generators.push_back(d);
  RigidSpec pole;
  pole.name = "pole";
  pole.shape.kind = ShapeKind::cylinder;
  pole.shape.radius = Real(0.02);
  pole.shape.height = Real(1.2);
  pole.position = Vec3(0, Real(1.6), 0);
  pole.orientation = rotation(Vec3::UnitX(), kPi / 2);  // local y along z
  s.bodies.push_back(ground());
  s.bodies.push_back(pole);
  s.solver.frames = 180;
  return s;
}

SceneSpec rope_pendulum() {
  // A 1 m rope of 21 particles, pinned at one end, carrying a 2 kg box
  // attached (two-way) 2 cm off the middle of one face (outside the box, so
  // that the rope's own contact with the box does not fight the
  // attachment); released from horizontal.
  SceneSpec s;
  s.name = "rope_pendulum";
  s.description = "21-particle rope pinned at one end carries a 2 kg rigid box, released horizontal";
  xpbd::RopeDesc r;
  r.n = 21;
  r.start = Vec3(0, Real(1.5), 0);
  r.dir = Vec3::UnitX();
  r.spacing = Real(0.05);
  r.mass = Real(0.005);
  r.pin_first = true;
  r.mat.compliance = Real(1e-8);
  s.soft.generators.push_back(r);
  const Vec3 end = r.start + Real(r.n - 1) * r.spacing * r.dir;
  const Real a = Real(0.1), gap = Real(0.02);  // m: box half extent, rope end to face
  s.bodies.push_back(box("box", Vec3::Constant(a), end + (a + gap) * r.dir, 2));
  s.attachments.push_back(AttachmentSpec{r.n - 1, 0, -(a + gap) * r.dir, 0});
  s.solver.substeps = 20;
  s.solver.iterations = 4;
  s.solver.frames = 180;
  return s;
}

SceneSpec trampoline() {
  // The integration test's trampoline (tests/integration/test_world_coupling):
  // a 10 kg ball on a 0.1 kg cloth pinned at its four corners, with the
  // settings that mass ratio needs (docs/bridge-limitations.md).
  SceneSpec s;
  s.name = "trampoline";
  s.description = "10 kg ball dropped onto a 0.1 kg cloth pinned at its 4 corners (100:1 mass ratio)";
  xpbd::ClothGridDesc d = flat_cloth(21, 1, Vec3::Zero(), Real(0.1), Real(1e-5));
  d.stretch = d.shear_mat = Material{Real(1e-5), Real(10), 1};
  d.bend_mat = Material{Real(1e-2), 0, 1};
  d.pins = xpbd::ClothPins::all_corners;
  s.soft.generators.push_back(d);
  RigidSpec ball = sphere("ball", Real(0.15), Vec3(0, Real(0.25), 0), 10);
  ball.linear_damping = ball.angular_damping = Real(0.5);
  s.bodies.push_back(ball);
  s.solver.substeps = 20;
  s.solver.iterations = 10;
  s.solver.alternate_sweeps = true;
  s.solver.frames = 240;
  return s;
}

SceneSpec soft_cube_stairs() {
  // The integration test's staircase as a static triangle mesh
  // (btBvhTriangleMeshShape), and a 0.2 m soft cube of tetrahedra (2x2x2
  // cells, 1 kg, bulk modulus 1 MPa) placed with its centre 3 cm past the
  // edge of the top step, so that it tips over and tumbles down.
  SceneSpec s;
  s.name = "soft_cube_stairs";
  s.description = "soft tetrahedral cube tips off the top of a static triangle-mesh staircase";
  constexpr int kSteps = 4;
  const Real rise = Real(0.1), run = Real(0.4), w = Real(0.5);
  RigidSpec stairs;
  stairs.name = "stairs";
  stairs.shape.kind = ShapeKind::mesh;
  auto quad = [&](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& e) {
    const int i = static_cast<int>(stairs.shape.vertices.size());
    for (const Vec3& p : {a, b, c, e}) stairs.shape.vertices.push_back(p);
    stairs.shape.triangles.push_back({i, i + 1, i + 2});
    stairs.shape.triangles.push_back({i, i + 2, i + 3});
  };
  for (int k = 0; k < kSteps; ++k) {
    const Real x0 = k * run, x1 = (k + 1) * run, y = Real(kSteps - k) * rise;
    const Real y_below = Real(kSteps - k - 1) * rise;
    quad(Vec3(x0, y, -w), Vec3(x0, y, w), Vec3(x1, y, w), Vec3(x1, y, -w));                  // tread, +y
    quad(Vec3(x1, y_below, -w), Vec3(x1, y, -w), Vec3(x1, y, w), Vec3(x1, y_below, w));      // riser, +x
  }
  s.bodies.push_back(ground());
  s.bodies.push_back(stairs);
  xpbd::TetBoxDesc c;
  c.nx = c.ny = c.nz = 2;
  c.size = Vec3::Constant(Real(0.2));
  c.origin = Vec3(Real(0.33), Real(kSteps) * rise + Real(0.01), Real(-0.1));
  c.mass = 1;
  c.bulk_modulus = Real(1e6);
  c.edge_mat.compliance = Real(1e-6);
  s.soft.generators.push_back(c);
  s.soft.contacts.thickness = Real(0.005);
  s.solver.iterations = 4;
  s.solver.frames = 240;
  return s;
}

// A unit icosphere: the icosahedron subdivided `levels` times, triangles
// counter-clockwise seen from outside.
xpbd::TriangleMesh icosphere(int levels) {
  xpbd::TriangleMesh m;
  const Real phi = (1 + std::sqrt(Real(5))) / 2;
  for (Real a : {Real(-1), Real(1)})
    for (Real b : {-phi, phi}) {
      m.positions.emplace_back(0, a, b);
      m.positions.emplace_back(a, b, 0);
      m.positions.emplace_back(b, 0, a);
    }
  // The 20 faces are the triples of mutually adjacent vertices (edge 2).
  auto adjacent = [&](int i, int j) {
    return std::abs((m.positions[i] - m.positions[j]).norm() - 2) < Real(1e-3);
  };
  for (int i = 0; i < 12; ++i)
    for (int j = i + 1; j < 12; ++j)
      for (int k = j + 1; k < 12; ++k) {
        if (!adjacent(i, j) || !adjacent(j, k) || !adjacent(i, k)) continue;
        const Vec3& a = m.positions[i];
        const bool outward = (m.positions[j] - a).cross(m.positions[k] - a).dot(a) > 0;
        m.triangles.push_back(outward ? xpbd::Triangle{i, j, k} : xpbd::Triangle{i, k, j});
      }
  for (Vec3& p : m.positions) p.normalize();
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<Index, Index>, Index> mid;
    auto midpoint = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      if (auto it = mid.find(key); it != mid.end()) return it->second;
      m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
      return mid[key] = static_cast<Index>(m.positions.size() - 1);
    };
    std::vector<xpbd::Triangle> next;
    for (const xpbd::Triangle& t : m.triangles) {
      const Index ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({ab, t[1], bc});
      next.push_back({ca, bc, t[2]});
      next.push_back({ab, bc, ca});
    }
    m.triangles = std::move(next);
  }
  return m;
}

SceneSpec balloon() {
  // A pressurised icosphere (162 particles, 320 triangles, global volume at
  // 1.5 x its initial volume) dropped onto the ground next to a box.
  SceneSpec s;
  s.name = "balloon";
  s.description = "pressure balloon (global volume 1.5 V0) inflates while it falls onto the ground";
  xpbd::TriangleMeshDesc d;
  d.kind = xpbd::MeshKind::closed_surface;
  d.scale = Real(0.3);
  d.offset = Vec3(0, Real(0.8), 0);
  d.mass = Real(0.5);
  d.edge_mat.compliance = Real(1e-3);
  d.pressure = Real(1.5);
  d.name = "icosphere";
  xpbd::add_triangle_mesh(s.soft.particles, icosphere(2), d);
  s.bodies.push_back(ground());
  s.bodies.push_back(box("box", Vec3(Real(0.15), Real(0.15), Real(0.15)), Vec3(Real(0.3), Real(0.15), 0), 0));
  s.solver.iterations = 4;
  s.solver.drag = 1;
  s.solver.frames = 180;
  return s;
}

SceneSpec two_cloths() {
  // Two cloths in one particle system with particle collision: the upper
  // one falls onto the lower one, which is pinned at its corners.
  SceneSpec s;
  s.name = "two_cloths";
  s.description = "a falling cloth lands on a corner-pinned cloth; particle collision between them";
  xpbd::ClothGridDesc lower = flat_cloth(20, 1, Vec3(0, Real(0.5), 0), Real(0.2), Real(1e-6));
  lower.pins = xpbd::ClothPins::all_corners;
  xpbd::ClothGridDesc upper = flat_cloth(16, Real(0.6), Vec3(Real(0.05), Real(0.7), Real(0.03)), Real(0.1), Real(1e-6));
  s.soft.generators.push_back(lower);
  s.soft.generators.push_back(upper);
  s.soft.particles.self_collision.enabled = true;
  s.soft.particles.self_collision.distance = Real(0.02);
  s.solver.iterations = 2;
  s.solver.frames = 150;
  return s;
}

SceneSpec bullet_softdemo_cloth() {
  // Port of Bullet's SoftDemo "Cloth" (Init_Cloth, examples/SoftDemo): a
  // 16 m x 16 m patch of 31 x 31 nodes, 150 kg, fixed at its four corners,
  // links and distance-2 bending links with kLST = 0.4, collision margin
  // 0.5 m, gravity -10 m/s^2, and Ctor_RbUpStack(10): ten 10 kg bodies at
  // (0, 2 + 6i, 0) cycling through a compound (a 4x1x1 box crossed with a
  // cylinder), a unit box (half extent 1) and a sphere of radius 1.5.
  // Differences: the compound is replaced by its box child (half extents
  // 4, 1, 1) (scene files have no compound shapes); the ground box at
  // y = -12 is a plane; XPBD needs a compliance where btSoftBody has kLST
  // (1e-4 m/N here; kLST = 0.4 is kept for --solver bullet).
  SceneSpec s;
  s.name = "bullet_softdemo_cloth";
  s.description = "port of Bullet SoftDemo 'Cloth': 10 heavy rigid bodies onto a 150 kg corner-pinned cloth";
  xpbd::ClothGridDesc d = flat_cloth(31, 16, Vec3::Zero(), 150, Real(1e-4));
  d.pins = xpbd::ClothPins::all_corners;
  s.soft.generators.push_back(d);
  s.soft.contacts.thickness = Real(0.5);
  s.soft.contacts.margin = Real(0.5);
  s.soft.contacts.feature_spacing = Real(0.25);
  s.solver.gravity = Vec3(0, -10, 0);
  s.solver.bullet_kLST = Real(0.4);
  s.bodies.push_back(ground(-12));
  for (int i = 0; i < 10; ++i) {
    const Vec3 at(0, Real(2 + 6 * i), 0);
    switch (i % 3) {
      case 0: s.bodies.push_back(box("bar" + std::to_string(i), Vec3(4, 1, 1), at, 10)); break;
      case 1: s.bodies.push_back(box("box" + std::to_string(i), Vec3(1, 1, 1), at, 10)); break;
      default: s.bodies.push_back(sphere("sphere" + std::to_string(i), Real(1.5), at, 10)); break;
    }
  }
  s.solver.substeps = 10;
  s.solver.iterations = 2;
  s.solver.frames = 240;
  return s;
}

SceneSpec bullet_softdemo_capsule() {
  // Port of Bullet's SoftDemo "CapsuleCollision" (Init_CapsuleCollision): a
  // static capsule along x (radius 1, cylinder length 5, margin 0.5,
  // friction 0.8) at (0, 4, 0) and an 8 m x 8 m patch of 20 x 20 nodes,
  // 0.1 kg, nothing fixed, released at y = 6; piterations = 10; gravity
  // -10 m/s^2; CreatePatch's material (kLST = 1). XPBD: 10 substeps x 1
  // iteration, compliance 1e-6 m/N.
  SceneSpec s;
  s.name = "bullet_softdemo_capsule";
  s.description = "port of Bullet SoftDemo 'CapsuleCollision': cloth draped over a static capsule";
  xpbd::ClothGridDesc d = flat_cloth(20, 8, Vec3(0, 6, 0), Real(0.1), Real(1e-6));
  s.soft.generators.push_back(d);
  s.soft.contacts.thickness = Real(0.5);
  s.soft.contacts.margin = Real(0.5);
  RigidSpec cap;
  cap.name = "capsule";
  cap.shape.kind = ShapeKind::capsule;
  cap.shape.radius = 1;
  cap.shape.height = 5;
  cap.position = Vec3(0, 4, 0);
  cap.orientation = rotation(Vec3::UnitZ(), kPi / 2);  // local y onto x
  cap.friction = Real(0.8);
  s.bodies.push_back(cap);
  s.solver.gravity = Vec3(0, -10, 0);
  s.solver.substeps = 10;
  s.solver.iterations = 1;
  s.solver.frames = 180;
  return s;
}

// ---------------------------------------------------------------------------
// Stiff scenes with an accuracy target (solver.tolerance, 5 % strain): what
// breaks a fixed budget (docs/tolerance.md). `substeps` is where the count
// starts; scripts/tolerance.sh compares each with fixed budgets.

SceneSpec stiff_light_cloth() {
  // A light, stiff cloth: 24 x 24, 0.6 m, 20 g, every edge 1e-9 m/N, flat,
  // pinned at the two corners of one edge.
  SceneSpec s;
  s.name = "stiff_light_cloth";
  s.description = "light stiff 24x24 cloth (20 g, 1e-9 m/N) pinned at two corners, tolerance 5 % strain";
  xpbd::ClothGridDesc d = flat_cloth(24, Real(0.6), Vec3(0, 0, Real(0.3)), Real(0.02), Real(1e-9));
  d.pinned = {{0, 0}, {23, 0}};
  s.soft.generators.push_back(d);
  s.solver.tolerance = 0.05;
  s.solver.frames = 180;
  return s;
}

SceneSpec large_cloth() {
  // A large cloth of 1 kg: 50 x 50, 2 m, every edge 1e-8 m/N, flat, pinned
  // at the two corners of one edge.
  SceneSpec s;
  s.name = "large_cloth";
  s.description = "50x50 cloth of 2 m and 1 kg (1e-8 m/N) pinned at two corners, tolerance 5 % strain";
  xpbd::ClothGridDesc d = flat_cloth(50, 2, Vec3(0, 0, 1), 1, Real(1e-8));
  d.pinned = {{0, 0}, {49, 0}};
  s.soft.generators.push_back(d);
  s.solver.tolerance = 0.05;
  s.solver.frames = 180;
  return s;
}

SceneSpec heavy_rope() {
  // A long stiff rope with a heavy end: 201 particles of 1 g, 1 cm links
  // (2 m), 1e-9 m/N, pinned at one end, carrying a 0.2 kg box attached to
  // its last particle (200 times the rope's particle mass); released
  // horizontal. Solved along the rope directly (solver.direct_chains), the
  // box included: the convergence aid that wins on it at every budget
  // measured (docs/convergence.md).
  SceneSpec s;
  s.name = "heavy_rope";
  s.description = "2 m rope of 201 particles (1 g each) pinned at one end, a 0.2 kg box at the other, direct solve along the rope, tolerance 5 % strain";
  xpbd::RopeDesc r;
  r.n = 201;
  r.start = Vec3(0, Real(2.5), 0);
  r.dir = Vec3::UnitX();
  r.spacing = Real(0.01);
  r.mass = Real(0.001);  // kg per particle
  r.pin_first = true;
  r.mat.compliance = Real(1e-9);
  s.soft.generators.push_back(r);
  const Vec3 end = r.start + Real(r.n - 1) * r.spacing * r.dir;
  const Real a = Real(0.05), gap = Real(0.01);  // m: box half extent, rope end to face
  s.bodies.push_back(box("box", Vec3::Constant(a), end + (a + gap) * r.dir, Real(0.2)));
  s.attachments.push_back(AttachmentSpec{r.n - 1, 0, -(a + gap) * r.dir, 0});
  s.solver.direct_chains = true;
  // The tolerance controller starts at 4 substeps: it rises at once where
  // the rope whips and falls slowly (docs/tolerance.md), so a start above
  // what the calm parts need is paid for 15 steps per fifth. Measured: a
  // mean of 4.16 substeps from 4, 5.61 from the library's 10.
  s.solver.substeps = 4;
  s.solver.tolerance = 0.05;
  s.solver.max_substeps = 400;
  s.solver.frames = 180;
  return s;
}

SceneSpec branched_rope() {
  // A stiff branched rope: a 0.4 m trunk of 1 cm links from a pin, and at
  // its end three 0.4 m branches, 30 degrees apart, each ending in a 50 g
  // weight; 1 g particles, 1e-9 m/N, released horizontal. Three or more
  // elements meet at the junction, so it is a tree, and direct_chains
  // solves it as one (docs/convergence.md, "Direct solve over trees").
  SceneSpec s;
  s.name = "branched_rope";
  s.description = "stiff rope branching into three 50 g weights, 1 g particles, pinned, direct solve over the tree, tolerance 5 % strain";
  xpbd::SceneDesc& d = s.soft.particles;
  const Real link = Real(0.01), m = Real(0.001);
  const int links = 40;
  auto add_link = [&](xpbd::Index a, xpbd::Index b) {
    xpbd::DistanceDesc e{a, b, link, {}};
    e.mat.compliance = Real(1e-9);
    d.distances.push_back(e);
  };
  xpbd::Index prev = d.add_particle(Vec3(0, Real(2.5), 0), 0);  // the pin
  for (int k = 1; k <= links; ++k) {
    const xpbd::Index p = d.add_particle(Vec3(link * Real(k), Real(2.5), 0), m);
    add_link(prev, p);
    prev = p;
  }
  const xpbd::Index junction = prev;
  for (int b = -1; b <= 1; ++b) {
    const Real angle = Real(b) * Real(0.5235987755982988);  // 30 degrees
    const Vec3 dir(std::cos(angle), 0, std::sin(angle));
    xpbd::Index q = junction;
    for (int k = 1; k <= links; ++k) {
      const xpbd::Index p = d.add_particle(d.positions[std::size_t(junction)] + link * Real(k) * dir, k == links ? Real(0.05) : m);
      add_link(q, p);
      q = p;
    }
  }
  s.solver.direct_chains = true;
  s.solver.substeps = 4;
  s.solver.tolerance = 0.05;
  s.solver.max_substeps = 400;
  s.solver.frames = 180;
  return s;
}

SceneSpec heavy_box_on_cloth() {
  // A light cloth pressed between a heavy body and the ground: 24 x 24,
  // 1 m, 0.4 kg, lying flat on a static plane at the contact thickness,
  // and a 1000 kg box (0.3 x 0.1 x 0.3 m) dropped from 0.2 m onto its
  // middle: a mass ratio of 2.4e6 to one particle. One sweep per substep
  // leaves the particles under the box inside the band between the two
  // bodies; the accuracy target here is on depth (solver.
  // penetration_tolerance, 1 mm inside the contact band), and the solver
  // picks the substeps that keep it (docs/tolerance.md).
  SceneSpec s;
  s.name = "heavy_box_on_cloth";
  s.description = "1000 kg box dropped onto a 0.4 kg 24x24 cloth lying on the ground, tolerance 1 mm penetration";
  const Real t = s.soft.contacts.thickness;
  xpbd::ClothGridDesc d = flat_cloth(24, 1, Vec3(0, t, 0), Real(0.4), 0);
  s.soft.generators.push_back(d);
  const Vec3 half(Real(0.15), Real(0.05), Real(0.15));
  s.bodies.push_back(ground());
  s.bodies.push_back(box("box", half, Vec3(0, 2 * t + half.y() + Real(0.2), 0), 1000));
  s.solver.penetration_tolerance = 0.001;
  s.solver.frames = 180;
  return s;
}

SceneSpec spinning_blade() {
  // A coarse cloth dropped onto a thin kinematic blade spinning about the
  // vertical at 20 rad/s: the blade's top edge (1 cm thick) sweeps 6.7 cm
  // per frame at its tips, between particles 14 cm apart, so only the rigid
  // features against the cloth's triangles, swept along their path over
  // the step (ContactSettings::sweep_features), keep the cloth on its side.
  SceneSpec s;
  s.name = "spinning_blade";
  s.description = "coarse 8x8 cloth onto a 1 cm blade spinning at 20 rad/s (swept feature-vs-triangle contacts)";
  xpbd::ClothGridDesc d = flat_cloth(8, 1, Vec3(0, Real(0.6), 0), Real(0.2), Real(1e-6));
  d.collision_triangles = true;
  s.soft.generators.push_back(d);
  s.soft.contacts.thickness = Real(0.005);
  s.soft.contacts.static_friction = s.soft.contacts.dynamic_friction = Real(0.8);
  RigidSpec blade = box("blade", Vec3(Real(0.2), Real(0.03), Real(0.005)), Vec3(0, Real(0.5), 0), 0);
  blade.kinematic = true;
  blade.angular_velocity = Vec3(0, 20, 0);
  s.bodies.push_back(ground());
  s.bodies.push_back(blade);
  s.solver.frames = 240;
  return s;
}

std::vector<SceneSpec> make_all() {
  std::vector<SceneSpec> v;
  v.push_back(cloth_on_sphere());
  v.push_back(hanging_cloth());
  v.push_back(cloth_on_box_corner());
  v.push_back(spinning_blade());
  v.push_back(flag());
  v.push_back(rope_pendulum());
  v.push_back(trampoline());
  v.push_back(soft_cube_stairs());
  v.push_back(balloon());
  v.push_back(two_cloths());
  v.push_back(bullet_softdemo_cloth());
  v.push_back(bullet_softdemo_capsule());
  v.push_back(stiff_light_cloth());
  v.push_back(large_cloth());
  v.push_back(heavy_rope());
  v.push_back(branched_rope());
  v.push_back(heavy_box_on_cloth());
  return v;
}

}  // namespace

const std::vector<SceneSpec>& builtin_scenes() {
  static const std::vector<SceneSpec> all = make_all();
  return all;
}

const SceneSpec* find_builtin_scene(const std::string& name) {
  for (const SceneSpec& s : builtin_scenes())
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace xpbd_demos
