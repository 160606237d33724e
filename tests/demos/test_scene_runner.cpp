// The scene runner (demos/scene_runner.hpp) against closed forms: free fall
// of a particle and of a rigid body through the metrics' energy series, the
// strain, penetration and particle-distance metrics on hand-built
// configurations, a kinematic body moving with its velocity, a body hanging
// from an attachment, a cloth resting on a box with every solver, refusals of
// what btSoftBody cannot express, input errors, and a run that goes
// non-finite. Every reference is written out here, never taken from the code
// under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "demos/scene_runner.hpp"
#include "xpbd/error.hpp"

namespace xpbd_demos {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;

constexpr Real kEps = std::numeric_limits<Real>::epsilon();
constexpr Real kG = Real(9.81);  // m/s^2
constexpr Solver kAllSolvers[] = {Solver::xpbd, Solver::pbd, Solver::bullet};

// btSoftRigidDynamicsWorld hands the soft body its internal step as a float
// (m_softBodySolver->predictMotion(float(timeStep))), so in a double build
// btSoftBody integrates with the step rounded to float.
Real soft_step(Solver s, Real h) {
  return s == Solver::bullet ? static_cast<Real>(static_cast<float>(h)) : h;
}

SceneSpec empty_scene(const char* name) {
  SceneSpec s;
  s.name = name;
  s.solver.gravity = Vec3(0, -kG, 0);
  return s;
}

RunOptions options(const SceneSpec& s, Solver solver, int frames, int substeps, int iterations = 1) {
  RunOptions o = run_options(s);
  o.solver = solver;
  o.frames = frames;
  o.substeps = substeps;
  o.iterations = iterations;
  return o;
}

// ---------------------------------------------------------------------------
// Free fall of one particle, no bodies. Every solver integrates a free
// particle with symplectic Euler over substeps (btSoftBody: internal steps)
// of h: v += g h, x += v h. After n steps from (y0, v0):
//   v_n = v0 - g h n,   y_n = y0 + v0 h n - g h^2 n (n + 1) / 2,
// so the metrics must give KE_n = m |v_n|^2 / 2 and PE_n = m g y_n, and the
// total drifts by exactly E_n - E_0 = -m g^2 h^2 n / 2 (symplectic Euler's
// energy error for a constant force).
// Round-off: each step recomputes v = (x - x_prev)/h, a difference of
// numbers of size |x| divided by h: ~eps |x| / h in v per step, summed over
// n steps in v and again in x (n^2/2 eps |x|). Bounds: twice that, with
// |x| + 1 for |x|.

class FreeFall : public ::testing::TestWithParam<Solver> {};

TEST_P(FreeFall, EnergySeriesMatchesDiscreteSymplecticEuler) {
  const Solver solver = GetParam();
  SceneSpec spec = empty_scene("free_fall");
  const Real m = Real(0.5), y0 = 2, vx = Real(0.3), vy = 1;
  spec.soft.particles.add_particle(Vec3(0, y0, 0), m, 0, Vec3(vx, vy, 0));
  const int frames = 30, substeps = 4;
  const RunOptions opt = options(spec, solver, frames, substeps);

  std::vector<Vec3> x;
  std::vector<int> seen;
  const RunResult r = run_scene(spec, opt, [&](const FrameView& f) {
    seen.push_back(f.frame);
    ASSERT_EQ(f.positions.size(), 1u);
    EXPECT_TRUE(f.bodies.empty());
    EXPECT_TRUE(f.finite);
    x.push_back(f.positions[0]);
  });
  ASSERT_TRUE(r.finite);
  ASSERT_EQ(r.frames_completed, frames);
  ASSERT_EQ(r.series.size(), std::size_t(frames + 1));
  ASSERT_EQ(seen.size(), std::size_t(frames + 1));
  for (int k = 0; k <= frames; ++k) EXPECT_EQ(seen[std::size_t(k)], k);

  const Real h = soft_step(solver, opt.dt / Real(substeps));
  for (int k = 0; k <= frames; ++k) {
    const Real n = Real(k * substeps);
    const Real y = y0 + vy * h * n - kG * h * h * n * (n + 1) / 2;
    const Real v = vy - kG * h * n;
    const Real ax = Real(1) + std::abs(y);
    const Real tol_x = 2 * std::max(Real(1), n * n) * kEps * ax;
    const Real tol_v = 2 * std::max(Real(1), n) * kEps * ax / h;
    const FrameMetrics& f = r.series[std::size_t(k)];
    EXPECT_NEAR(x[std::size_t(k)].y(), y, tol_x) << "frame " << k;
    EXPECT_NEAR(x[std::size_t(k)].x(), vx * h * n, tol_x) << "frame " << k;
    EXPECT_NEAR(f.time, double(k) * double(opt.dt), 1e-12) << "frame " << k;
    // KE error from v: m |v| dv; PE error from y: m g dy.
    EXPECT_NEAR(f.kinetic_energy, double(m * (vx * vx + v * v) / 2), double(m * (std::abs(v) + 1) * tol_v))
        << "frame " << k;
    EXPECT_NEAR(f.potential_energy, double(m * kG * y), double(m * kG * tol_x)) << "frame " << k;
    const double drift = f.kinetic_energy + f.potential_energy - (r.series[0].kinetic_energy + r.series[0].potential_energy);
    EXPECT_NEAR(drift, double(-m * kG * kG * h * h * n / 2),
                double(m * (std::abs(v) + 1) * tol_v + 2 * m * kG * tol_x))
        << "frame " << k;
  }
  // Nothing to strain or penetrate.
  EXPECT_EQ(r.max_strain, 0.0);
  EXPECT_EQ(r.max_penetration, 0.0);
  EXPECT_FALSE(r.particle_collision);
  EXPECT_EQ(r.projections_per_frame, 0);
}

INSTANTIATE_TEST_SUITE_P(Solvers, FreeFall, ::testing::ValuesIn(kAllSolvers),
                         [](const auto& i) { return std::string(solver_name(i.param)); });

// A dynamic rigid body falls with Bullet's integrator, which is symplectic
// Euler over one internal step per frame for xpbd/pbd and `substeps` per
// frame for bullet. Its energies are part of the metrics: KE = m v^2 / 2 and
// PE = m g y (no rotation). The one particle is kinematic and far away (no
// energy, no contact).
TEST(SceneRunner, RigidBodyEnergiesInTheSeries) {
  for (Solver solver : kAllSolvers) {
    SceneSpec spec = empty_scene("falling_ball");
    spec.soft.particles.add_particle(Vec3(50, 0, 0), 0);
    RigidSpec ball;
    ball.shape.kind = ShapeKind::sphere;
    ball.shape.radius = Real(0.2);
    ball.mass = 3;
    ball.position = Vec3(0, 5, 0);
    spec.bodies.push_back(ball);
    const int frames = 20, substeps = solver == Solver::bullet ? 2 : 5;
    const RunOptions opt = options(spec, solver, frames, substeps);
    std::vector<Vec3> pos;
    const RunResult r = run_scene(spec, opt, [&](const FrameView& f) {
      ASSERT_EQ(f.bodies.size(), 1u);
      pos.push_back(f.bodies[0].position);
    });
    ASSERT_TRUE(r.finite);
    // Bullet's rigid step is the full internal step (not rounded to float).
    const Real h = solver == Solver::bullet ? opt.dt / Real(substeps) : opt.dt;
    const int steps_per_frame = solver == Solver::bullet ? substeps : 1;
    for (int k = 0; k <= frames; ++k) {
      const Real n = Real(k * steps_per_frame);
      const Real y = 5 - kG * h * h * n * (n + 1) / 2;
      const Real v = -kG * h * n;
      // Round-off: v accumulates n additions of g h (n eps |v| each at
      // most), x accumulates those (n^2 eps |x|); |x| <= 6 m here.
      const Real tol_x = 4 * std::max(Real(1), n * n) * kEps * 6;
      const Real tol_v = 4 * std::max(Real(1), n) * kEps * (std::abs(v) + 1);
      EXPECT_NEAR(pos[std::size_t(k)].y(), y, tol_x) << solver_name(solver) << " frame " << k;
      EXPECT_NEAR(r.series[std::size_t(k)].kinetic_energy, double(3 * v * v / 2),
                  double(3 * (std::abs(v) + 1) * tol_v))
          << solver_name(solver) << " frame " << k;
      EXPECT_NEAR(r.series[std::size_t(k)].potential_energy, double(3 * kG * y), double(3 * kG * tol_x))
          << solver_name(solver) << " frame " << k;
    }
  }
}

// RunOptions::rigid_steps splits an xpbd/pbd frame into that many Bullet
// steps: a falling ball then follows symplectic Euler with h = dt/K,
// y_n = y0 - g h^2 n (n+1)/2 after n = K * frame steps -- which differs from
// one step per frame by g dt^2 frame (1 - 1/K)/2, far above the tolerance.
// Invalid values name the field.
TEST(SceneRunner, RigidStepsStepTheBodiesThatManyTimesPerFrame) {
  for (Solver solver : {Solver::xpbd, Solver::pbd}) {
    SceneSpec spec = empty_scene("falling_ball");
    spec.soft.particles.add_particle(Vec3(50, 0, 0), 0);
    RigidSpec ball;
    ball.shape.kind = ShapeKind::sphere;
    ball.shape.radius = Real(0.2);
    ball.mass = 3;
    ball.position = Vec3(0, 5, 0);
    spec.bodies.push_back(ball);
    const int frames = 6, K = 4;
    RunOptions opt = options(spec, solver, frames, 8);
    opt.rigid_steps = K;
    std::vector<Vec3> pos;
    const RunResult r = run_scene(spec, opt, [&](const FrameView& f) { pos.push_back(f.bodies[0].position); });
    ASSERT_TRUE(r.finite);
    EXPECT_EQ(r.solver_settings.at("rigid_steps_per_frame").get<int>(), K);
    const Real h = opt.dt / Real(K);
    for (int k = 0; k <= frames; ++k) {
      const Real n = Real(k * K);
      const Real y = 5 - kG * h * h * n * (n + 1) / 2;
      const Real tol_x = 4 * std::max(Real(1), n * n) * kEps * 6;  // as in RigidBodyEnergiesInTheSeries
      EXPECT_NEAR(pos[std::size_t(k)].y(), y, tol_x) << solver_name(solver) << " frame " << k;
    }
    const Real one_step = 5 - kG * opt.dt * opt.dt * Real(frames) * Real(frames + 1) / 2;
    // The control: one Bullet step per frame would be off by g dt^2 F (1 - 1/K) / 2 = 6.1 mm, more than
    // twice the final tolerance even in float (1.7 mm).
    EXPECT_GT(std::abs(pos.back().y() - one_step), 2 * 4 * Real(frames * K * frames * K) * kEps * 6);
  }
  SceneSpec spec = empty_scene("p");
  spec.soft.particles.add_particle(Vec3(0, 0, 0), 1);
  for (auto [solver, substeps, k] : {std::tuple{Solver::xpbd, 8, 3}, std::tuple{Solver::xpbd, 8, 0},
                                     std::tuple{Solver::bullet, 8, 2}}) {
    RunOptions opt = options(spec, solver, 2, substeps);
    opt.rigid_steps = k;
    try {
      run_scene(spec, opt);
      ADD_FAILURE() << "rigid_steps " << k << " accepted";
    } catch (const xpbd::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("solver.rigid_steps"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(std::to_string(k)), std::string::npos) << e.what();
    }
  }
}

// A kinematic box moves with its velocity and angular velocity: after t
// seconds its centre is at x0 + v t.
TEST(SceneRunner, KinematicBodyMovesWithItsVelocity) {
  for (Solver solver : kAllSolvers) {
    SceneSpec spec = empty_scene("kinematic");
    spec.soft.particles.add_particle(Vec3(50, 0, 0), 0);
    RigidSpec box;
    box.shape.kind = ShapeKind::box;
    box.kinematic = true;
    box.position = Vec3(1, 2, 3);
    box.velocity = Vec3(Real(0.5), Real(-0.25), 1);
    box.angular_velocity = Vec3(0, 1, 0);
    spec.bodies.push_back(box);
    const RunOptions opt = options(spec, solver, 30, 3);
    std::vector<BodyPose> poses;
    run_scene(spec, opt, [&](const FrameView& f) { poses.push_back(f.bodies[0]); });
    ASSERT_EQ(poses.size(), 31u);
    for (std::size_t k = 0; k < poses.size(); ++k) {
      const Real t = Real(k) * opt.dt;
      const Vec3 expect = box.position + box.velocity * t;
      EXPECT_LT((poses[k].position - expect).norm(), 256 * kEps * 4) << solver_name(solver) << " frame " << k;
      // Rotation about y by angle t (rad/s * s): q = (cos(t/2), 0, sin(t/2), 0).
      const auto& q = poses[k].orientation;
      const Real sign = q[0] < 0 ? Real(-1) : Real(1);
      EXPECT_NEAR(sign * q[0], std::cos(t / 2), 1024 * kEps) << solver_name(solver) << " frame " << k;
      EXPECT_NEAR(sign * q[2], std::sin(t / 2), 1024 * kEps) << solver_name(solver) << " frame " << k;
    }
  }
}

// ---------------------------------------------------------------------------
// The strain metric on a hand-stretched chain. Three kinematic particles
// (mass 0: nothing moves them) at x = 0, 1.1, 2.3 m with rest lengths 1 m:
// strains |1.1/1 - 1| = 0.1 and |1.2/1 - 1| = 0.2, so max 0.2, mean 0.15, in
// the initial state and after every frame. Round-off: a few eps of the
// lengths.
TEST(SceneRunner, StrainOfAHandStretchedChainIsTheClosedForm) {
  for (Solver solver : kAllSolvers) {
    SceneSpec spec = empty_scene("stretched");
    auto& d = spec.soft.particles;
    d.add_particle(Vec3(0, 0, 0), 0);
    d.add_particle(Vec3(Real(1.1), 0, 0), 0);
    d.add_particle(Vec3(Real(2.3), 0, 0), 0);
    d.distances.push_back(xpbd::DistanceDesc{0, 1, Real(1), {}});
    d.distances.push_back(xpbd::DistanceDesc{1, 2, Real(1), {}});
    const RunResult r = run_scene(spec, options(spec, solver, 3, 2));
    ASSERT_TRUE(r.finite);
    for (const FrameMetrics& f : r.series) {
      EXPECT_NEAR(f.max_strain, 0.2, 16 * kEps) << solver_name(solver);
      EXPECT_NEAR(f.mean_strain, 0.15, 16 * kEps) << solver_name(solver);
    }
    EXPECT_NEAR(r.max_strain, 0.2, 16 * kEps);
    EXPECT_NEAR(r.mean_strain, 0.15, 16 * kEps);
    EXPECT_EQ(r.distance_constraints, 2);
  }
}

// ---------------------------------------------------------------------------
// The penetration metric: (radius + thickness) - signed distance of a
// movable particle from the surface, in the initial state. Particle radius
// r = 0.02 m, thickness t = 0.005 m, no gravity, so frame 0 is exact:
//   - centre 0.4 m from the centre of a sphere of radius 0.5 m: signed
//     distance -0.1 m, penetration 0.125 m;
//   - 0.05 m deep under the top face of a box: 0.075 m (the sphere's is
//     deeper, so the maximum is 0.125 m);
// then the same scene without the sphere particle (0.075 m) and with only a
// particle farther than r + t outside every body (0).
TEST(SceneRunner, PenetrationMetricIsRadiusPlusThicknessMinusSignedDistance) {
  const Real r = Real(0.02), t = Real(0.005);
  auto scene = [&](bool in_sphere, bool in_box) {
    SceneSpec spec = empty_scene("penetration");
    spec.solver.gravity = Vec3::Zero();
    spec.soft.contacts.thickness = t;
    auto& d = spec.soft.particles;
    d.add_particle(in_sphere ? Vec3(Real(0.4), 0, 0) : Vec3(0, Real(0.5) + r + t + Real(0.01), 0), 1, r);
    d.add_particle(in_box ? Vec3(3, Real(0.05), 0) : Vec3(3, Real(0.1) + r + t + Real(0.01), 0), 1, r);
    RigidSpec sphere;
    sphere.shape.kind = ShapeKind::sphere;
    sphere.shape.radius = Real(0.5);
    spec.bodies.push_back(sphere);
    RigidSpec box;
    box.shape.kind = ShapeKind::box;
    box.shape.half_extents = Vec3(Real(0.3), Real(0.1), Real(0.3));
    box.position = Vec3(3, 0, 0);
    spec.bodies.push_back(box);
    return spec;
  };
  for (Solver solver : kAllSolvers) {
    const Real tol = 64 * kEps;
    auto pen0 = [&](const SceneSpec& s) { return run_scene(s, options(s, solver, 1, 1)).series[0].max_penetration; };
    EXPECT_NEAR(pen0(scene(true, true)), double(r + t + Real(0.1)), tol) << solver_name(solver);
    EXPECT_NEAR(pen0(scene(false, true)), double(r + t + Real(0.05)), tol) << solver_name(solver);
    EXPECT_EQ(pen0(scene(false, false)), 0.0) << solver_name(solver);
  }
}

// ---------------------------------------------------------------------------
// min_particle_distance: measured only with particle collision on, over the
// pairs that may collide. Three movable particles at rest without gravity:
// 0 and 1 joined by a distance constraint 0.01 m apart (a connected pair,
// excluded by skip_connected), 2 at 0.3 m from 0 and 0.31 m from 1. The
// contact distance is 0.05 m, so nothing touches or moves, and the smallest
// distance of a colliding pair is 0.3 m (found beyond the first search
// radius of 2 x 0.05 m, so the search must grow).
TEST(SceneRunner, MinParticleDistanceOverCollidingPairs) {
  SceneSpec spec = empty_scene("pairs");
  spec.solver.gravity = Vec3::Zero();
  auto& d = spec.soft.particles;
  d.add_particle(Vec3(0, 0, 0), 1);
  d.add_particle(Vec3(Real(-0.01), 0, 0), 1);
  d.add_particle(Vec3(Real(0.3), 0, 0), 1);
  d.distances.push_back(xpbd::DistanceDesc{0, 1, std::nullopt, {}});
  d.self_collision.enabled = true;
  d.self_collision.distance = Real(0.05);
  for (Solver solver : {Solver::xpbd, Solver::pbd}) {
    const RunResult r = run_scene(spec, options(spec, solver, 2, 2));
    ASSERT_TRUE(r.particle_collision);
    ASSERT_TRUE(r.min_particle_distance.has_value());
    EXPECT_NEAR(*r.min_particle_distance, 0.3, 16 * kEps);
    for (const FrameMetrics& f : r.series) {
      ASSERT_TRUE(f.min_particle_distance.has_value());
      EXPECT_NEAR(*f.min_particle_distance, 0.3, 16 * kEps);
    }
    const nlohmann::json j = to_json(r);
    EXPECT_NEAR(j.at("min_particle_distance").get<double>(), 0.3, 16 * kEps);
  }
  // Without particle collision the field is absent.
  d.self_collision.enabled = false;
  const RunResult off = run_scene(spec, options(spec, Solver::xpbd, 1, 1));
  EXPECT_FALSE(off.min_particle_distance.has_value());
  EXPECT_FALSE(to_json(off).contains("min_particle_distance"));
}


// ---------------------------------------------------------------------------
// A cloth dropped onto a static box, with each solver.
SceneSpec cloth_on_box(xpbd::HingeBending bending = xpbd::HingeBending::none) {
  SceneSpec spec = empty_scene("cloth_on_box");
  xpbd::ClothGridDesc c;
  c.nx = c.ny = 11;
  c.size_u = c.size_v = Real(0.5);
  c.origin = Vec3(Real(-0.25), Real(0.3), Real(-0.25));
  c.u = Vec3::UnitX();
  c.v = Vec3::UnitZ();
  c.mass = Real(0.2);
  c.hinge_bending = bending;
  spec.soft.generators.push_back(c);
  spec.soft.contacts.thickness = Real(0.005);
  RigidSpec box;
  box.shape.kind = ShapeKind::box;
  box.shape.half_extents = Vec3(Real(0.15), Real(0.1), Real(0.15));
  spec.bodies.push_back(box);
  return spec;
}

// XPBD and PBD (same settings: one iteration of stiffness-1 constraints
// with compliance 0 project identically) keep every particle out of the box
// (max_penetration below the thickness; contacts are projected last in
// every iteration, so only round-off remains where the contact plane holds),
// and the centre particle, lying on the flat top face at the end, sits at
// the top (0.1 m) plus the thickness to within one substep's fall g h^2,
// which the contact undoes every substep. btSoftBody runs the same scene with
// finite metrics; its numbers are printed, not asserted (its contacts and
// friction work differently, see docs/metrics.md: this cloth drifts off the
// box within 1.5 s).
TEST(SceneRunner, ClothOnBoxWithEverySolver) {
  for (Solver solver : kAllSolvers) {
    const SceneSpec spec = cloth_on_box();
    const RunOptions opt = options(spec, solver, 60, 10);
    Vec3 centre = Vec3::Zero();
    int calls = 0;
    const RunResult r = run_scene(spec, opt, [&](const FrameView& f) {
      ++calls;
      ASSERT_EQ(f.positions.size(), 121u);
      ASSERT_EQ(f.bodies.size(), 1u);
      EXPECT_EQ(f.bodies[0].position, Vec3::Zero());  // static
      centre = f.positions[60];  // particle (5, 5)
    });
    EXPECT_EQ(calls, 61);
    ASSERT_TRUE(r.finite) << solver_name(solver);
    EXPECT_EQ(r.frames_completed, 60);
    EXPECT_EQ(r.frame_ms.size(), 60u);
    EXPECT_EQ(r.particles, 121);
    for (const FrameMetrics& f : r.series) {
      EXPECT_TRUE(std::isfinite(f.kinetic_energy) && std::isfinite(f.potential_energy) &&
                  std::isfinite(f.max_strain) && std::isfinite(f.max_penetration));
      EXPECT_GE(f.max_penetration, 0.0);
    }
    const nlohmann::json j = to_json(r);
    EXPECT_EQ(j.at("solver"), solver_name(solver));
    EXPECT_EQ(j.at("finite"), true);
    EXPECT_EQ(j.at("per_frame").size(), 61u);
    EXPECT_EQ(j.at("scalar"), sizeof(Real) == 8 ? "double" : "float");
    std::printf("%-6s max_penetration %.3g m  max_strain %.3g  mean_strain %.3g  centre y %.5f m  "
                "%.3f ms/frame  %lld projections/frame\n",
                solver_name(solver), r.max_penetration, r.max_strain, r.mean_strain, double(centre.y()),
                r.wall_ms_median, r.projections_per_frame);
    if (solver == Solver::bullet) {
      EXPECT_EQ(r.solver_settings.at("piterations"), 1);
      EXPECT_EQ(r.solver_settings.at("internal_steps_per_frame"), 10);
      EXPECT_EQ(r.projections_per_frame, 10LL * r.distance_constraints);
      continue;
    }
    const Real h = opt.dt / Real(opt.substeps);
    EXPECT_LT(r.max_penetration, double(spec.soft.contacts.thickness)) << solver_name(solver);
    EXPECT_NEAR(centre.y(), Real(0.1) + spec.soft.contacts.thickness, kG * h * h) << solver_name(solver);
  }
}

// A 1 kg box hangs from a kinematic particle by an attachment at the centre
// of its top face (local point (0, 0.1, 0), here taken from where the
// particle starts), starting at rest in equilibrium.
//   - XPBD/PBD: the attachment is projected after Bullet moved the body, so
//     the box ends every frame exactly where it hangs: y = 0.9 m (round-off).
//   - btSoftBody: an anchor corrects the body's velocity, not its position,
//     after Bullet integrated it: each internal step of h the body first falls
//     by g h^2 from rest, then the anchor sets the velocity that brings it
//     back during the next step, where gravity again takes g h^2. Steady
//     state: y = 0.9 - g h^2 after every internal step (h = dt / 4 here,
//     relative round-off of h: float's epsilon, as btSoftBody's step is
//     rounded to float).
TEST(SceneRunner, BoxHangingFromAnAttachment) {
  for (Solver solver : kAllSolvers) {
    for (bool explicit_local : {false, true}) {
      SceneSpec spec = empty_scene("hang");
      spec.soft.particles.add_particle(Vec3(0, 1, 0), 0);
      RigidSpec box;
      box.shape.kind = ShapeKind::box;
      box.shape.half_extents = Vec3::Constant(Real(0.1));
      box.mass = 1;
      box.position = Vec3(0, Real(0.9), 0);
      spec.bodies.push_back(box);
      AttachmentSpec a;
      if (explicit_local) a.local = Vec3(0, Real(0.1), 0);
      spec.attachments.push_back(a);
      ASSERT_TRUE(bullet_can_express(spec));
      const RunOptions opt = options(spec, solver, 60, 4);
      const Real h = opt.dt / Real(opt.substeps);
      const Real sag = solver == Solver::bullet ? kG * h * h : Real(0);
      const Real tol = solver == Solver::bullet ? Real(1e-6) * kG * h * h + 64 * kEps : 64 * kEps;
      const RunResult r = run_scene(spec, opt, [&](const FrameView& f) {
        if (f.frame == 0) return;
        EXPECT_NEAR(f.bodies[0].position.y(), Real(0.9) - sag, tol)
            << solver_name(solver) << " frame " << f.frame;
        EXPECT_NEAR(f.bodies[0].position.x(), 0, 64 * kEps);
      });
      EXPECT_TRUE(r.finite);
      // The attached particle is not measured against its own body.
      EXPECT_EQ(r.max_penetration, 0.0);
    }
  }
}

// ---------------------------------------------------------------------------
// What btSoftBody cannot express is refused with a message naming it.
TEST(SceneRunner, BulletRefusesDihedralBendingNamingIt) {
  const SceneSpec bent = cloth_on_box(xpbd::HingeBending::dihedral);
  std::string why;
  EXPECT_FALSE(bullet_can_express(bent, &why));
  // 11 x 11 grid: interior edges of the triangulation = 3 * 10 * 10 - 2 * 10 = 280 hinges.
  EXPECT_NE(why.find("dihedral_bends: scene has 280 dihedral bending elements"), std::string::npos) << why;
  try {
    run_scene(bent, options(bent, Solver::bullet, 1, 1));
    ADD_FAILURE() << "bullet ran a scene with dihedral bending";
  } catch (const xpbd::SceneError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("--solver bullet: ", 0), 0u) << m;
    EXPECT_NE(m.find("dihedral"), std::string::npos) << m;
  }
  // XPBD runs it.
  EXPECT_TRUE(run_scene(bent, options(bent, Solver::xpbd, 2, 2)).finite);

  // Every reason is listed.
  SceneSpec many = cloth_on_box();
  auto& c = std::get<xpbd::ClothGridDesc>(many.soft.generators[0]);
  c.pins = xpbd::ClothPins::top_corners;
  c.tethers = xpbd::TetherAnchors::nearest_pinned;
  many.soft.contacts.restitution = Real(0.5);
  many.attachments.push_back(AttachmentSpec{5, 0, std::nullopt, Real(1e-3)});
  EXPECT_FALSE(bullet_can_express(many, &why));
  for (const char* what : {"tethers: scene has 119 tethers", "soft.contacts.restitution",
                           "attachments[0].compliance"})
    EXPECT_NE(why.find(what), std::string::npos) << what << " not in: " << why;
  EXPECT_TRUE(bullet_can_express(cloth_on_box(), &why));
  EXPECT_EQ(why, "");
}

// ---------------------------------------------------------------------------
// Invalid input: an error naming the field and the value, before anything runs.
TEST(SceneRunner, InvalidInputNamesTheField) {
  auto message = [](const SceneSpec& spec, const RunOptions& opt) -> std::string {
    try {
      run_scene(spec, opt);
    } catch (const std::invalid_argument& e) {  // ConfigError and SceneError
      return e.what();
    }
    return "";
  };
  const SceneSpec good = cloth_on_box();
  RunOptions o = options(good, Solver::xpbd, 1, 1);
  o.substeps = 0;
  EXPECT_EQ(message(good, o), "solver.substeps: must be >= 1, got 0");
  o = options(good, Solver::bullet, 1, 1);
  o.dt = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_NE(message(good, o).find("solver.dt: must be finite and > 0"), std::string::npos);
  o = options(good, Solver::xpbd, 0, 1);
  EXPECT_EQ(message(good, o), "solver.frames: must be >= 1, got 0");

  o = options(good, Solver::xpbd, 1, 1);
  SceneSpec s = good;
  s.bodies[0].mass = -1;
  EXPECT_EQ(message(s, o), "bodies[0].mass: must be finite and >= 0, got -1");
  s = good;
  s.bodies[0].shape.half_extents.y() = 0;
  EXPECT_EQ(message(s, o), "bodies[0].shape.half_extents: must be finite and > 0, got 0");
  s = good;
  s.bodies[0].velocity = Vec3(1, 0, 0);
  EXPECT_NE(message(s, o).find("bodies[0].velocity: a static body"), std::string::npos);
  s = good;
  s.attachments.push_back(AttachmentSpec{3, 4, std::nullopt, 0});
  EXPECT_EQ(message(s, o), "attachments[0].body: index 4 out of range [0, 1)");
  s = good;
  s.attachments.push_back(AttachmentSpec{121, 0, std::nullopt, 0});
  EXPECT_EQ(message(s, o), "attachments[0].particle: index 121 out of range [0, 121)");
  s = good;
  s.soft.contacts.dynamic_friction = 2;
  EXPECT_NE(message(s, o).find("soft.contacts.dynamic_friction: must be <= static_friction"), std::string::npos);
  s = good;
  s.solver.bullet_kLST = 0;
  EXPECT_EQ(message(s, options(s, Solver::bullet, 1, 1)), "solver.bullet_kLST: must be in (0, 1], got 0");
}

// ---------------------------------------------------------------------------
// A run that goes non-finite stops after that frame with finite = false and
// still gives its metrics. Two particles fly apart at +-max/8 m/s joined by
// a distance constraint: after one substep their distance squared overflows,
// the constraint's length is +inf and its correction inf * 0 = NaN. No
// solver survives that: every one must stop after frame 1.
TEST(SceneRunner, NonFiniteRunStopsAndReportsIt) {
  for (Solver solver : kAllSolvers) {
    SceneSpec spec = empty_scene("blow_up");
    const Real v = std::numeric_limits<Real>::max() / 8;
    auto& d = spec.soft.particles;
    d.add_particle(Vec3(0, 0, 0), 1, 0, Vec3(v, 0, 0));
    d.add_particle(Vec3(1, 0, 0), 1, 0, Vec3(-v, 0, 0));
    d.distances.push_back(xpbd::DistanceDesc{0, 1, std::nullopt, {}});
    std::vector<bool> finite;
    const RunResult r = run_scene(spec, options(spec, solver, 10, 2), [&](const FrameView& f) {
      finite.push_back(f.finite);
    });
    EXPECT_FALSE(r.finite) << solver_name(solver);
    EXPECT_EQ(r.frames_completed, 1) << solver_name(solver);
    ASSERT_EQ(finite.size(), 2u);
    EXPECT_TRUE(finite[0]);
    EXPECT_FALSE(finite[1]);
    ASSERT_EQ(r.series.size(), 2u);
    EXPECT_TRUE(std::isnan(r.series[1].max_strain));
    const nlohmann::json j = to_json(r);
    EXPECT_EQ(j.at("finite"), false);
    EXPECT_TRUE(j.at("per_frame")[1].at("kinetic_energy").is_number());  // NaN is a number here
    EXPECT_FALSE(j.dump().empty());  // dump writes NaN as null
    EXPECT_NE(j.dump().find("null"), std::string::npos);
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd_demos
