// step() checks the particle contacts and attachments of a State before it
// solves (xpbd/src/rigid_checks.cpp): each bad field is a ConfigError that
// names the list, the element, the field and the value, and the state is
// left as it was. Before, a NaN normal or attachment point, a negative
// thickness or a NaN friction went into the solve unnoticed, and a
// negative attachment compliance threw the particle 1e5 m away in three
// steps. (Friction and restitution <= 0 are allowed: they mean none.)
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "xpbd/rigid_solve.hpp"
#include "xpbd/xpbd.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;

// step() throws a ConfigError whose message contains `named`, and leaves
// the particles where they were.
void expect_refused(const xpbd::Model& m, xpbd::State& s, const char* named) {
  const std::vector<Vec3> before = s.x;
  try {
    xpbd::step(m, s, xpbd::StepConfig{});
    ADD_FAILURE() << named << ": accepted";
  } catch (const xpbd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
  }
  EXPECT_EQ(s.x, before) << named;
}

struct Bad {
  const char* named;  // what the message must contain
  std::function<void(xpbd::BodyContact&, xpbd::BodyAttachment&)> spoil;
};

TEST(RigidChecks, BadContactOrAttachmentFieldIsAConfigErrorNamingIt) {
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const Real inf = std::numeric_limits<Real>::infinity();
  using C = xpbd::BodyContact;
  using A = xpbd::BodyAttachment;
  const std::vector<Bad> bad = {
      {"state.contacts[1].n: (nan, 1, 0)", [&](C& c, A&) { c.n = Vec3(nan, 1, 0); }},
      {"state.contacts[1].n: (0, 2, 0)", [](C& c, A&) { c.n = Vec3(0, 2, 0); }},
      {"state.contacts[1].r: (0, inf, 0)", [&](C& c, A&) { c.r = Vec3(0, inf, 0); }},
      {"state.contacts[1].thickness: -1", [](C& c, A&) { c.thickness = -1; }},
      {"state.contacts[1].compliance: -0.5", [](C& c, A&) { c.compliance = Real(-0.5); }},
      {"state.contacts[1].static_friction: nan", [&](C& c, A&) { c.static_friction = nan; }},
      {"state.contacts[1].dynamic_friction: inf", [&](C& c, A&) { c.dynamic_friction = inf; }},
      {"state.contacts[1].restitution: nan", [&](C& c, A&) { c.restitution = nan; }},
      {"state.attachments[0].r: (nan, 0, 0)", [&](C&, A& a) { a.r = Vec3(nan, 0, 0); }},
      {"state.attachments[0].compliance: -0.125", [](C&, A& a) { a.compliance = Real(-0.125); }},
      {"state.attachments[0].compliance: inf", [&](C&, A& a) { a.compliance = inf; }},
  };
  for (const Bad& b : bad) {
    xpbd::SceneDesc scene;
    scene.add_particle(Vec3(0, Real(0.004), 0), Real(1e-3));
    const xpbd::Model m = xpbd::compile(scene);
    xpbd::State s = xpbd::make_state(m);
    xpbd::BodyContact good;  // the ground under the particle
    good.particle = 0;
    good.body = -1;
    good.thickness = Real(0.005);
    xpbd::BodyContact c = good;
    xpbd::BodyAttachment a;  // a fixed point 1 cm up
    a.particle = 0;
    a.body = -1;
    a.r = Vec3(0, Real(0.01), 0);
    b.spoil(c, a);
    s.contacts = {good, c};
    s.attachments = {a};
    expect_refused(m, s, b.named);
  }
}

// The same for a rigid feature against a soft triangle.
TEST(RigidChecks, BadTriangleContactFieldIsAConfigErrorNamingIt) {
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const struct {
    const char* named;
    std::function<void(xpbd::BodyTriangleContact&)> spoil;
  } bad[] = {
      {"state.triangle_contacts[0].r: (0.25, 0.0078125, nan)", [&](xpbd::BodyTriangleContact& c) { c.r.z() = nan; }},
      {"state.triangle_contacts[0].side: 0", [](xpbd::BodyTriangleContact& c) { c.side = 0; }},
      {"state.triangle_contacts[0].thickness: -0.25", [](xpbd::BodyTriangleContact& c) { c.thickness = Real(-0.25); }},
      {"state.triangle_contacts[0].static_friction", [&](xpbd::BodyTriangleContact& c) { c.dynamic_friction = nan; }},
      {"state.triangle_contacts[0]: reach = -1", [](xpbd::BodyTriangleContact& c) { c.reach = -1; }},
  };
  for (const auto& b : bad) {
    xpbd::SceneDesc scene;
    for (const Vec3& x : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)}) scene.add_particle(x, Real(0.1));
    const xpbd::Model m = xpbd::compile(scene);
    xpbd::State s = xpbd::make_state(m);
    xpbd::BodyTriangleContact c;  // a fixed point 7.8 mm above the triangle
    c.r = Vec3(Real(0.25), Real(0.0078125), Real(0.25));
    c.tri = {0, 1, 2};
    c.thickness = Real(0.005);
    b.spoil(c);
    s.triangle_contacts = {c};
    expect_refused(m, s, b.named);
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
