// metrics.json's "forces" (demos/run_forces.hpp, xpbd/forces.hpp) against
// closed forms computed here from the scenes' own parameters:
//  - the compare harness's hanging chain (n particles of mass m, pinned at
//    the top, kinematic): (n - 1) m |g| upward at the pin, and the largest
//    Distance force is the top link's tension, the same (n - 1) m |g|;
//  - a box of mass M hanging at rest from ropes attached to it: the
//    attachments together carry M |g| (force on the box upward), and the
//    pins carry the box and the hanging rope particles.
#include <gtest/gtest.h>

#include <cstdio>
#include <variant>

#include "demos/compare/compare.hpp"
#include "demos/run_forces.hpp"
#include "demos/scene_runner.hpp"

namespace xpbd_demos {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;

Vec3 vec(const nlohmann::json& j) { return Vec3(j.at(0).get<Real>(), j.at(1).get<Real>(), j.at(2).get<Real>()); }

TEST(RunForces, HangingChainPinCarriesNMinusOneWeights) {
  xpbd_compare::ChainParams p;
  const SceneSpec spec = xpbd_compare::chain_scene(p, 120);
  RunOptions o = run_options(spec);
  o.substeps = 20;  // the budget of CompareChain.ConvergedXpbdRunCarries190N (test_compare.cpp)
  o.iterations = 20;
  const RunResult r = run_scene(spec, o);
  ASSERT_TRUE(r.finite);
  ASSERT_TRUE(r.forces.has_value());
  const nlohmann::json j = to_json(r).at("forces");
  // Closed form from the scene's parameters: the top particle is kinematic,
  // n - 1 particles of mass m hang from it.
  const double expected = double(p.n - 1) * double(p.mass) * double(p.g);
  const nlohmann::json& pins = j.at("pins");
  ASSERT_EQ(pins.at("count").get<int>(), 1);
  ASSERT_EQ(pins.at("listed").get<std::string>(), "all");
  const nlohmann::json& pin = pins.at("items").at(0);
  EXPECT_EQ(pin.at("particle").get<int>(), 0);
  EXPECT_FALSE(pin.at("from_balance").get<bool>());
  const Vec3 f = vec(pin.at("force"));
  std::printf("chain: pin force (%.9g, %.9g, %.9g) N after %d frames at %d x %d, expected (0, %.9g, 0), rel. %.3g\n",
              double(f.x()), double(f.y()), double(f.z()), r.frames_completed, o.substeps, o.iterations, expected,
              std::abs(double(f.y()) - expected) / expected);
  // 1e-3 of 190 N: the settling and convergence budget of test_compare's
  // position-based check (there 0.19 N); upward, against gravity.
  EXPECT_NEAR(f.y(), expected, 1e-3 * expected);
  EXPECT_NEAR(f.x(), 0, 1e-3 * expected);
  EXPECT_NEAR(f.z(), 0, 1e-3 * expected);
  EXPECT_NEAR(vec(pins.at("total")).y(), expected, 1e-3 * expected);
  // The largest Distance force: the top link's tension.
  const nlohmann::json& d = j.at("max_constraint_force").at("distance");
  EXPECT_EQ(d.at("unit").get<std::string>(), "N");
  EXPECT_EQ(d.at("element").get<int>(), 0);
  EXPECT_EQ(d.at("count").get<int>(), p.n - 1);
  EXPECT_NEAR(d.at("max").get<double>(), expected, 1e-3 * expected);
  EXPECT_GT(j.at("substep").get<double>(), 0);
}

// One or two vertical ropes of n particles (mass m, pinned at the top,
// kinematic) hold a box of mass M by their lower ends, attached at points
// above its top face (outside the box, as in the built-in rope_pendulum),
// above its centre of mass or symmetric about it; everything starts at rest at the unstretched
// lengths and settles (particle drag, body damping).
SceneSpec hanging_box(Real attachment_compliance, int ropes, int n, Real m, Real M, Real g) {
  SceneSpec s;
  s.name = "hanging_box";
  s.description = "box hanging at rest from two ropes attached to it";
  // Near the origin (the box's centre at y = -0.12 m): small coordinates
  // keep the float build's round-off far below g h^2 = 2.8e-5 m.
  const Real a = Real(0.1), gap = Real(0.02), spacing = Real(0.05), top = Real(0.25);
  const Real x_of[2] = {ropes == 1 ? Real(0) : -a, a};
  for (int k = 0; k < ropes; ++k) {
    xpbd::RopeDesc r;
    r.n = n;
    r.start = Vec3(x_of[k], top, 0);
    r.dir = -Vec3::UnitY();
    r.spacing = spacing;
    r.mass = m;
    r.pin_first = true;
    r.mat.compliance = Real(1e-8);
    s.soft.generators.emplace_back(std::in_place_type<xpbd::RopeDesc>, r);
  }
  const Real end_y = top - Real(n - 1) * spacing;
  RigidSpec b;
  b.name = "box";
  b.shape.kind = ShapeKind::box;
  b.shape.half_extents = Vec3::Constant(a);
  b.position = Vec3(0, end_y - gap - a, 0);
  b.mass = M;
  b.linear_damping = b.angular_damping = Real(0.5);
  s.bodies.push_back(b);
  for (int k = 0; k < ropes; ++k)
    s.attachments.push_back(AttachmentSpec{(k + 1) * n - 1, 0, Vec3(x_of[k], a + gap, 0), attachment_compliance});
  s.solver.gravity = Vec3(0, -g, 0);
  s.solver.substeps = 10;
  s.solver.iterations = 20;
  s.solver.drag = 5;
  s.solver.frames = 240;
  return s;
}

TEST(RunForces, HangingBoxAttachmentsCarryItsWeight) {
  const int n = 6;
  const Real m = Real(0.01), M = 2, g = 10;
  // Two compliant attachments are the case where lambda times the final
  // direction (x_p - p_b)/|x_p - p_b| was wrong: each one's last correction
  // moves the other's point by about its stretch (measured with the box at
  // 1.1 m and 20 substeps: 0.29 N sideways of 20 N at 1e-6 m/N);
  // State::attachment_impulse keeps each projection's direction.
  struct Case {
    Real alpha;
    int ropes;
  };
  for (const Case& cs : {Case{0, 2}, Case{Real(1e-6), 2}, Case{0, 1}, Case{Real(1e-6), 1}}) {
    const Real alpha = cs.alpha;
    const int ropes = cs.ropes;
    const SceneSpec spec = hanging_box(alpha, ropes, n, m, M, g);
    const RunResult r = run_scene(spec, run_options(spec));
    ASSERT_TRUE(r.finite);
    ASSERT_TRUE(r.forces.has_value());
    const nlohmann::json j = to_json(r).at("forces");
    const nlohmann::json& atts = j.at("attachments");
    ASSERT_EQ(atts.at("count").get<int>(), ropes);
    const double weight = double(M) * double(g);
    Vec3 sum = Vec3::Zero();
    for (const auto& e : atts.at("items")) {
      EXPECT_EQ(e.at("body").get<int>(), 0);
      EXPECT_EQ(e.at("body_name").get<std::string>(), "box");
      const Vec3 on_body = vec(e.at("on_body"));
      EXPECT_EQ(vec(e.at("on_particle")), Vec3(-on_body));
      // By symmetry each carries an equal share.
      EXPECT_NEAR(on_body.y(), weight / ropes, 5e-3 * weight) << e.dump();
      sum += on_body;
    }
    const Vec3 total = vec(atts.at("total"));
    std::printf("box (%d rope(s), attachment alpha %g): attachments on the box (%.9g, %.9g, %.9g) N, expected (0, %.9g, 0), "
                "rel. %.3g\n",
                ropes, double(alpha), double(total.x()), double(total.y()), double(total.z()), weight,
                std::abs(double(total.y()) - weight) / weight);
    EXPECT_NEAR((sum - total).norm(), 0, 1e-9 * weight);
    EXPECT_NEAR(total.y(), weight, 5e-3 * weight);
    EXPECT_NEAR(total.x(), 0, 5e-3 * weight);
    EXPECT_NEAR(total.z(), 0, 5e-3 * weight);
    // The pins carry the box and the ropes' n - 1 particles below each pin.
    const double carried = (double(M) + double(ropes) * double(n - 1) * double(m)) * double(g);
    const Vec3 pins = vec(j.at("pins").at("total"));
    std::printf("box: pins (%.9g, %.9g, %.9g) N, expected (0, %.9g, 0)\n", double(pins.x()), double(pins.y()),
                double(pins.z()), carried);
    EXPECT_EQ(j.at("pins").at("count").get<int>(), ropes);
    EXPECT_NEAR(pins.y(), carried, 5e-3 * carried);
  }
}

// Beyond kForcesListedMax pins: the count and total of all, the largest few.
TEST(RunForces, LongListsAreBounded) {
  RunForces f;
  const int n = int(kForcesListedMax) + 500;
  for (int i = 0; i < n; ++i) f.pins.push_back(xpbd::PinReaction{i, -1, Vec3(0, Real(i % 7), 0), false});
  const nlohmann::json j = forces_json(f).at("pins");
  EXPECT_EQ(j.at("count").get<int>(), n);
  EXPECT_EQ(j.at("listed").get<std::string>(), "largest");
  ASSERT_EQ(j.at("items").size(), kForcesListed);
  for (const auto& e : j.at("items")) EXPECT_EQ(e.at("magnitude").get<double>(), 6.0) << e.dump();
  double total = 0;
  for (int i = 0; i < n; ++i) total += double(i % 7);
  EXPECT_EQ(vec(j.at("total")).y(), Real(total));
  f.pins.resize(kForcesListedMax);
  const nlohmann::json all = forces_json(f).at("pins");
  EXPECT_EQ(all.at("listed").get<std::string>(), "all");
  EXPECT_EQ(all.at("items").size(), kForcesListedMax);
}

TEST(RunForces, NotForPbd) {
  xpbd_compare::ChainParams p;
  const SceneSpec spec = xpbd_compare::chain_scene(p, 2);
  RunOptions o = run_options(spec);
  o.solver = Solver::pbd;
  const RunResult r = run_scene(spec, o);
  EXPECT_FALSE(r.forces.has_value());
  EXPECT_FALSE(to_json(r).contains("forces"));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd_demos
