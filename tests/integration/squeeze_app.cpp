// The bar-squeeze application (squeeze_app.hpp).
#include "squeeze_app.hpp"

#include <random>

#include "xpbd_bullet/narrowphase.hpp"

namespace xpbd_bullet::test::squeeze {

void add_random_bodies(BulletWorld& bw, int bodies, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const Vec3 lo = kBarStart - kBarHalf - Vec3(0, 1, 0), hi = kBarStart + kBarHalf;  // bar and cloth
  std::vector<std::pair<Vec3, Real>> placed;  // centre, bounding radius
  const auto clear = [&](const Vec3& at, Real r) {
    if ((at.cwiseMax(lo).cwiseMin(hi) - at).norm() < r + Real(0.01)) return false;
    for (const auto& [c, rc] : placed)
      if ((c - at).norm() < r + rc + Real(0.01)) return false;
    return true;
  };
  for (int k = 0; k < bodies; ++k) {
    const Real size = Real(0.05 + 0.1 * u(rng));
    Vec3 at;
    do at = Vec3(Real(-1 + 2 * u(rng)), Real(0.3 + 3 * u(rng)), Real(-1 + 2 * u(rng)));
    while (!clear(at, Real(1.8) * size));
    placed.emplace_back(at, Real(1.8) * size);
    const Real mass = Real(0.1 + 1.9 * u(rng));
    btCollisionShape* shape = nullptr;
    switch (k % 4) {
      case 0: shape = new btSphereShape(size); break;
      case 1: shape = new btBoxShape(btVector3(size, Real(0.7) * size, Real(1.3) * size)); break;
      case 2: shape = new btCapsuleShape(Real(0.5) * size, 2 * size); break;
      default: {
        auto* hull = new btConvexHullShape();
        for (int v = 0; v < 8; ++v)
          hull->addPoint(btVector3(Real(size * (2 * u(rng) - 1)), Real(size * (2 * u(rng) - 1)),
                                   Real(size * (2 * u(rng) - 1))));
        shape = hull;
      }
    }
    btTransform pose = BulletWorld::at(at);
    pose.setRotation(btQuaternion(btVector3(Real(u(rng)), Real(u(rng)), Real(u(rng) + 0.1)).normalized(),
                                  Real(3 * u(rng))));
    bw.add_body(shape, mass, pose);
  }
}


xpbd_bullet::SystemId add_cloth(XpbdWorld& xw, btRigidBody* bar, const SystemSettings& set, bool triangles,
                                unsigned wrinkle_seed, Real bend, Real shear) {
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc c;
  c.nx = c.ny = kN;
  c.size_u = c.size_v = 1;
  c.mass = kClothMass;
  c.origin = kBarStart + Vec3(-0.5, -kBarHalf.y(), 0);
  c.collision_triangles = triangles;
  c.bend_mat.compliance = bend;
  c.shear_mat.compliance = shear;
  const xpbd::ClothGrid grid = xpbd::add_cloth_grid(scene, c);
  std::mt19937 rng(wrinkle_seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < kN * kN; ++i) scene.positions[std::size_t(grid.first + i)].z() += kWrinkle * Real(u(rng));
  System sys = make_system(scene);
  const auto id = xw.add_system(sys.model, sys.state, set);
  for (int i : kAttached)
    xw.attach(id, grid.first + i, bar, bt(sys.model->x0[std::size_t(grid.first + i)] - kBarStart));
  return id;
}


Result run(int bodies, bool cloth, int contact_sweeps, bool after_solve, int substeps, unsigned wrinkle_seed,
           int frames, double penetration, bool wedges, bool surface_edges, double strain,
           const std::function<void(SystemSettings&)>& tweak, Real bend, Real shear) {
  BulletWorld bw;
  bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
  btRigidBody* bar = bw.add_body(new btBoxShape(bt(kBarHalf)), kBarMass, BulletWorld::at(kBarStart));
  add_random_bodies(bw, bodies);
  XpbdWorld xw(bw.world());
  SystemSettings set;  // the defaults, but for the arguments
  set.contact_sweeps = contact_sweeps;
  set.contacts.settle = set.contacts.spacers = after_solve;
  set.contacts.wedges = wedges;
  set.contacts.surface_edge_contacts = surface_edges;
  if (substeps > 0) set.substeps = substeps;
  set.tolerance.penetration = penetration;
  set.tolerance.strain = strain;
  if (tweak) tweak(set);
  xpbd_bullet::SystemId id;
  if (cloth) id = add_cloth(xw, bar, set, false, wrinkle_seed, bend, shear);
  Result r;
  r.sweeps_per_step = 0;
  std::vector<const btCollisionObject*> near;
  std::vector<bool> attached(std::size_t(kN * kN), false);
  for (int i : kAttached) attached[std::size_t(i)] = true;
  for (int f = 0; f < frames; ++f) {
    bw.step();
    r.bar.push_back(vec(bar->getCenterOfMassPosition()));
    if (!cloth) continue;
    const xpbd::Health status = xw.health(id).status;
    r.exploded = r.exploded || (f > 0 && status == xpbd::Health::exploded) || status == xpbd::Health::nonfinite;
    const xpbd::State& s = xw.state(id);
    const xpbd::Model& m = xw.model(id);
    Vec3 lo = s.x[0], hi = s.x[0];
    for (const Vec3& x : s.x) {
      if (!x.allFinite()) {
        r.finite = false;
        return r;
      }
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
    xpbd_bullet::candidates(bw.world(), lo, hi, near);
    // The strain; each edge over 20 % counted, and whether its midpoint is
    // inside a body or below the ground (an edge through a body, which
    // particle contacts alone cannot stop).
    bool over = false;
    for (const xpbd::Distance& d : m.get<xpbd::Distance>()) {
      const Real e = ((s.x[d.p[0]] - s.x[d.p[1]]).norm() - d.rest) / d.rest;
      r.strain = std::max(r.strain, e);
      if (!(e > Real(0.2))) continue;
      over = true;
      ++r.edges_over;
      const Vec3 mid = (s.x[d.p[0]] + s.x[d.p[1]]) / 2;
      bool through = mid.y() < 0, through_bar = false;
      for (const btCollisionObject* o : near) {
        xpbd_bullet::ParticleContact pc;
        const bool in = xpbd_bullet::query_point(*o, mid, 0, pc) && pc.distance < 0;
        through = through || in;
        through_bar = through_bar || (in && o == bar);
      }
      r.edges_through += through;
      r.edges_through_bar += through_bar;
      if (through && (attached[std::size_t(d.p[0])] || attached[std::size_t(d.p[1])])) ++r.edges_through_attached;
    }
    r.frames_over += over;
    Real deepest = 0;
    std::size_t at = 0;
    const btCollisionObject* in = nullptr;
    for (const btCollisionObject* o : near)
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        xpbd_bullet::ParticleContact pc;
        if (xpbd_bullet::query_point(*o, s.x[i], 0, pc) && -pc.distance > deepest) {
          deepest = -pc.distance;
          at = i;
          in = o;
        }
      }
    r.deepest = std::max(r.deepest, deepest);
    if (deepest > xpbd_bullet::ContactSettings{}.thickness) {
      ++r.frames_deep;
      for (const btCollisionObject* o : near) {
        xpbd_bullet::ParticleContact pc;
        if (o != in && xpbd_bullet::query_point(*o, s.x[at], Real(0.01), pc)) {
          ++r.frames_squeezed;
          break;
        }
      }
    }
  }
  if (cloth) r.sweeps_per_step = double(xw.state(id).sweeps) / frames;
  return r;
}

}  // namespace xpbd_bullet::test::squeeze
