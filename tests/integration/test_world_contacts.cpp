// Integration tests of XpbdWorld contacts against static rigid bodies in a
// real Bullet world: cloth draped on a sphere, cloth on a slope (static and
// dynamic Coulomb friction), a fast particle against a thin plate
// (tunnelling), and a supporting body removed from the world.
//
// Scenes run at Bullet's usual 60 Hz with one internal step per
// stepSimulation call. Every reference is a closed form stated next to the
// assertion, with the reasoning behind its tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "fits.hpp"
#include "support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

// A horizontal square cloth of n x n particles, side `size` m, total mass
// `mass` kg, centred at `centre`; no pins. Inextensible structural and shear
// edges (compliance 0) and soft bending edges, as a cloth is: it stretches
// little and folds easily.
struct Cloth {
  std::shared_ptr<const xpbd::Model> model;
  xpbd::State state;
  xpbd::ClothGrid grid;
};

Cloth make_cloth(int n, Real size, Real mass, const Vec3& centre, const Vec3& u = Vec3::UnitX(),
                 const Vec3& v = Vec3::UnitZ()) {
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc d;
  d.nx = d.ny = n;
  d.size_u = d.size_v = size;
  d.u = u;
  d.v = v;
  d.origin = centre - Real(0.5) * size * (u + v);
  d.mass = mass;
  d.bend_mat.compliance = Real(1e-2);  // m/N: bending edges give way to a few newtons
  Cloth c;
  c.grid = xpbd::add_cloth_grid(scene, d);
  auto m = std::make_shared<xpbd::Model>(xpbd::compile(scene));
  c.state = xpbd::make_state(*m);
  c.model = std::move(m);
  return c;
}

// ---------------------------------------------------------------------------
// 1. Cloth dropped on a static sphere comes to rest and never enters it.

TEST(WorldContacts, ClothDroppedOnSphereComesToRestWithoutPenetration) {
  BulletWorld bw;
  const Real R = Real(0.3);  // m, sphere radius
  const Vec3 c0(0, 0, 0);
  bw.add_static_sphere(R, c0);
  XpbdWorld xw(bw.world());

  // 1 m x 1 m cloth, 0.2 kg, dropped from 0.2 m above the sphere's top.
  const Real mass = Real(0.2), drop = Real(0.2);
  Cloth cloth = make_cloth(21, 1, mass, Vec3(0, R + drop, 0));
  SystemSettings set;
  set.substeps = 10;
  set.iterations = 2;
  set.contacts.thickness = Real(0.01);  // m
  const auto id = xw.add_system(cloth.model, cloth.state, set);
  const xpbd::Model& m = xw.model(id);
  const Real thick = set.contacts.thickness;  // particle radius is 0

  // Penetration depth of a particle (m): how far inside the thickened
  // sphere (radius R + thickness) its centre is; positive = deeper than the
  // thickness allows. The requirement is depth < thickness for the whole run,
  // i.e. no particle centre ever inside the sphere itself.
  Real worst = -1;
  // 8 s: the cloth creeps over the sphere until friction holds it. (Until
  // the contact refresh replaced a pair's contact instead of adding a
  // second one, refreshed pairs were solved twice per sweep, with twice the
  // friction, and the cloth was at rest within 5 s.)
  const int steps = 8 * 60;
  std::vector<Real> ke;
  for (int k = 0; k < steps; ++k) {
    bw.step();
    const xpbd::State& s = xw.state(id);
    for (const Vec3& x : s.x) worst = std::max(worst, R + thick - (x - c0).norm());
    ke.push_back(xpbd::kinetic_energy(m, s));
  }
  std::printf("max penetration into the thickened sphere: %.3g m (thickness %.3g m)\n", worst, thick);
  std::printf("kinetic energy at 1, 2, 4, 8 s: %.3g %.3g %.3g %.3g J\n", ke[59], ke[119], ke[239],
              ke[steps - 1]);
  EXPECT_LT(worst, thick);

  // At rest: the energy the fall released is of the order m g (drop + R)
  // = 0.2 * 9.81 * 0.5 ~ 1 J. "At rest" is taken as less than 1e-4 of that
  // (a mean particle speed of ~1 cm/s) over the whole last second.
  const Real released = mass * kG * (drop + R);
  for (int k = steps - 60; k < steps; ++k) ASSERT_LT(ke[k], Real(1e-4) * released) << "step " << k;

  // ... and at rest *on* the sphere, not slid off it: the middle particle
  // sits on the sphere's top at distance R + thickness from its centre. The
  // contact is solved to C = 0 every substep; what gravity adds before the
  // next projection is g h^2 = 2.7e-5 m (h = 1/600 s), so 1e-3 m is generous.
  const Vec3 top = xw.state(id).x[cloth.grid.at(10, 10)];
  EXPECT_NEAR((top - c0).norm(), R + thick, Real(1e-3));
  EXPECT_GT(top.y(), R);
}

// ---------------------------------------------------------------------------
// 5. Cloth on a slope: Coulomb friction. With mu > tan(theta) it sticks;
// with mu < tan(theta) it slides with a = g (sin(theta) - mu cos(theta)).

struct SlopeRun {
  std::vector<Real> t;  // s
  std::vector<Real> s;  // m, centre of mass along the downhill direction
  Real max_height = 0;  // m, largest distance of a particle from the slope surface
  Real min_height = 0;  // m, smallest (negative = below the surface)
};

// A static box whose top face is a plane tilted by theta about z; a 0.3 m
// cloth lies on it, 5 mm above, and is released at rest. The soft friction
// coefficients are mu (static and dynamic); the box's friction is 1, so the
// combined coefficient (product, as Bullet combines two rigid bodies) is mu.
SlopeRun run_slope(Real theta, Real mu, Real seconds) {
  BulletWorld bw;
  const btQuaternion tilt(btVector3(0, 0, 1), theta);
  const Vec3 up(-std::sin(theta), std::cos(theta), 0);        // slope normal
  const Vec3 downhill(-std::cos(theta), -std::sin(theta), 0);  // steepest descent
  const Vec3 half(4, Real(0.1), 1);                             // m, box half extents
  bw.add_static_box(half, btTransform(tilt, btVector3(0, 0, 0)), 1);
  XpbdWorld xw(bw.world());

  SystemSettings set;
  set.substeps = 10;
  set.iterations = 2;
  set.contacts.thickness = Real(0.005);
  set.contacts.static_friction = mu;
  set.contacts.dynamic_friction = mu;
  // Top face centre is half.y along `up`; start the cloth 5 mm above the
  // thickness layer, 2 m uphill of the centre so that it can slide 4 m.
  const Vec3 centre = half.y() * up + Real(0.01) * up - Real(2) * downhill;
  Cloth cloth = make_cloth(8, Real(0.3), Real(0.1), centre, -downhill, Vec3::UnitZ());
  const auto id = xw.add_system(cloth.model, cloth.state, set);

  SlopeRun r;
  r.min_height = 1e9;
  const int steps = static_cast<int>(std::lround(seconds / kDt));
  for (int k = 0; k < steps; ++k) {
    bw.step();
    const xpbd::State& s = xw.state(id);
    r.t.push_back(Real(k + 1) * kDt);
    r.s.push_back(centre_of_mass(xw.model(id), s).dot(downhill));
    if (k * kDt > Real(0.2)) {  // after landing
      for (const Vec3& x : s.x) {
        const Real h = x.dot(up) - half.y();
        r.max_height = std::max(r.max_height, h);
        r.min_height = std::min(r.min_height, h);
      }
    }
  }
  return r;
}

TEST(WorldContacts, ClothOnSlopeSticksWhenFrictionExceedsTangent) {
  const Real theta = Real(20) * kPi / 180;
  const Real mu = Real(1.5) * std::tan(theta);  // 0.55: a 50% margin over the sticking limit
  const SlopeRun r = run_slope(theta, mu, Real(2.5));
  // Settled after 0.5 s (it lands within 0.05 s); then 2 s of holding.
  const Real drift = r.s.back() - r.s[29];
  std::printf("stick: drift over 2 s %.3g m, height above surface in [%.4g, %.4g] m\n", drift,
              r.min_height, r.max_height);
  // Position-level static friction undoes all tangential motion within the
  // cone, so the expected drift is 0 up to round-off. Sliding at the
  // frictionless rate would cover g sin(theta) t^2 / 2 = 6.7 m in 2 s; even the
  // 1/3 of it that a 1.5x-too-weak friction gives is 2.2 m. 1 mm separates
  // sticking from any sliding by more than three orders of magnitude.
  EXPECT_LT(std::abs(drift), Real(1e-3));
  // Resting on the surface: no particle below it.
  EXPECT_GT(r.min_height, Real(0));
}

TEST(WorldContacts, ClothOnSlopeSlidesWithCoulombAcceleration) {
  const Real theta = Real(20) * kPi / 180;
  const Real mu = Real(0.5) * std::tan(theta);  // 0.18
  const SlopeRun r = run_slope(theta, mu, Real(1.5));
  // Fit s(t) = s0 + v0 t + a t^2 / 2 over 0.3 s .. 1.5 s (settled on the
  // slope; 73 samples).
  std::vector<Real> t(r.t.begin() + 17, r.t.end()), s(r.s.begin() + 17, r.s.end());
  const Quadratic q = fit_quadratic(t, s);
  const Real a_ref = kG * (std::sin(theta) - mu * std::cos(theta));
  std::printf("slide: a = %.5g m/s^2, reference %.5g (error %.3g%%), height in [%.4g, %.4g] m\n", q.a,
              a_ref, 100 * (q.a / a_ref - 1), r.min_height, r.max_height);
  // 5% (the stated requirement). Discretisation: dynamic friction removes
  // mu * (normal impulse) per substep, exactly Coulomb's law for a flat
  // contact; the remaining error is the cloth's internal motion, which the
  // centre-of-mass average removes.
  EXPECT_NEAR(q.a, a_ref, Real(0.05) * a_ref);
  EXPECT_GT(r.min_height, Real(0));
}

// ---------------------------------------------------------------------------
// 6. A particle at 50 m/s against a 1 cm plate at 60 Hz does not tunnel:
// it travels 0.83 m per step, 83 times the plate's thickness.

class FastParticle : public ::testing::TestWithParam<int> {};

TEST_P(FastParticle, StopsOnTheNearSideOfAThinPlate) {
  BulletWorld bw;
  const Real half_thick = Real(0.005);  // m, plate half thickness (1 cm plate)
  bw.add_static_box(Vec3(Real(0.5), half_thick, Real(0.5)), BulletWorld::at(Vec3::Zero()));
  XpbdWorld xw(bw.world());

  xpbd::SceneDesc scene;
  scene.add_particle(Vec3(Real(0.1), Real(1), Real(-0.2)), 1, 0, Vec3(0, -50, 0));
  auto m = std::make_shared<xpbd::Model>(xpbd::compile(scene));
  SystemSettings set;
  set.substeps = GetParam();
  set.contacts.thickness = Real(0.002);
  const auto id = xw.add_system(m, xpbd::make_state(*m), set);

  // Two seconds: the impact (step 2) and 1.9 s of resting on the plate under
  // gravity. The particle must stay on the near side: above the plate's top
  // face at every step. Expected rest height: top + thickness.
  Real lowest = 1e9;
  for (int k = 0; k < 120; ++k) {
    bw.step();
    lowest = std::min(lowest, xw.state(id).x[0].y());
  }
  const Vec3 x = xw.state(id).x[0];
  std::printf("substeps %d: lowest %.6g m, final %.6g m (plate top %.3g m)\n", GetParam(), lowest,
              x.y(), half_thick);
  EXPECT_GT(lowest, half_thick);
  // Resting height: contact solved to C = 0 each substep; gravity's push
  // before the next projection is g h^2 <= 2.8e-3 m at one substep, so the
  // particle sits within g h^2 (plus round-off) of top + thickness.
  const Real h = kDt / Real(GetParam());
  EXPECT_NEAR(x.y(), half_thick + set.contacts.thickness, kG * h * h + 64 * kEps);
  // It was stopped, not deflected: x and z unchanged (normal incidence, the
  // contact normal is exactly +y, so nothing acts along x or z; a few ulp).
  EXPECT_NEAR(x.x(), Real(0.1), 16 * kEps);
  EXPECT_NEAR(x.z(), Real(-0.2), 16 * kEps);
}

INSTANTIATE_TEST_SUITE_P(Substeps, FastParticle, ::testing::Values(1, 2, 5, 20));

// ---------------------------------------------------------------------------
// 7. A rigid body removed from the world while cloth rests on it: the next
// steps run and the cloth falls freely. Internal constraints conserve
// momentum, so the centre of mass follows the discrete free fall exactly:
// after n substeps of h, y_n = y0 + n h v0 - g h^2 n (n + 1) / 2, a quadratic
// in t = n h with second derivative exactly -g.

class RemovedSupport : public ::testing::TestWithParam<bool> {};

TEST_P(RemovedSupport, ClothFallsFreelyAfterItsSupportIsRemovedAndDeleted) {
  const bool dynamic = GetParam();
  BulletWorld bw;
  // The support: a 1 m x 0.2 m x 1 m box with its top at y = 0.5. Static, or
  // dynamic (10 kg) resting on a static ground whose top is at y = 0.3.
  btRigidBody* support = nullptr;
  if (dynamic) {
    bw.add_static_box(Vec3(2, Real(0.1), 2), BulletWorld::at(Vec3(0, Real(0.2), 0)));
    support = bw.add_body(new btBoxShape(btVector3(Real(0.5), Real(0.1), Real(0.5))), 10,
                          BulletWorld::at(Vec3(0, Real(0.4), 0)));
  } else {
    support = bw.add_static_box(Vec3(Real(0.5), Real(0.1), Real(0.5)), BulletWorld::at(Vec3(0, Real(0.4), 0)));
  }
  XpbdWorld xw(bw.world());
  SystemSettings set;
  set.contacts.thickness = Real(0.005);
  Cloth cloth = make_cloth(12, Real(0.6), Real(0.1), Vec3(0, Real(0.52), 0));
  const auto id = xw.add_system(cloth.model, cloth.state, set);
  for (int k = 0; k < 60; ++k) bw.step();  // 1 s: landed and resting
  const Real rest_y = centre_of_mass(xw.model(id), xw.state(id)).y();
  EXPECT_NEAR(rest_y, Real(0.5) + set.contacts.thickness, Real(2e-3)) << "not resting on the support";

  bw.remove_and_delete(support);  // a dangling cached pointer would be a use-after-free (ASan)
  // 0.2 s of free fall: g t^2 / 2 = 0.196 m, less than the 0.2 m gap down
  // to the ground of the dynamic case. Sample the centre of mass at every
  // step end.
  std::vector<Real> t, y;
  for (int k = 1; k <= 12; ++k) {
    bw.step();
    // The first step after the removal finds neither the body nor (dynamic
    // case) the ground, 0.2 m below: no contact at all.
    if (k == 1) {
      EXPECT_EQ(xw.last_stats().contacts, 0);
    }
    t.push_back(k * kDt);
    y.push_back(centre_of_mass(xw.model(id), xw.state(id)).y());
  }
  const Quadratic q = fit_quadratic(t, y);
  std::printf("%s support removed: a = %.12g m/s^2\n", dynamic ? "dynamic" : "static", q.a);
  // The fit is exact for the discrete free fall; what remains is round-off:
  // heights of ~0.5 m carry ~eps * 0.5 m, and the fit divides them by the
  // span (0.2 s)^2, so ~12 eps m/s^2 per unit of error (1e-11 m/s^2 is
  // observed in double). A single leftover contact (one particle held for
  // one step) would change a by ~g/144 ~ 7e-2 m/s^2. The tolerance,
  // 1e-6 g in double and 1e4 eps g (1.2e-3 g) in float, sits between the two.
  EXPECT_NEAR(q.a, -kG, std::max(Real(1e-6), Real(1e4) * kEps) * kG);
}

INSTANTIATE_TEST_SUITE_P(StaticAndDynamic, RemovedSupport, ::testing::Bool());

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
