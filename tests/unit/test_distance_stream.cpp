// The compiled coloured Distance sweep (distance_stream.hpp): what step()
// runs with StepConfig::coloured in XPBD.
//   - Model::distance_stream holds the elements of distance_colours.order,
//     and follows set_material;
//   - one sweep of the stream kernel computes what the pair-distance kernel
//     computes over the same elements in the same order (solve.hpp,
//     project_all_coloured), to round-off: undamped, damped, reversed, with
//     pinned particles;
//   - the AVX2 and the scalar kernel give the same results bit for bit over
//     30 steps of a falling cloth (skipped on a CPU without AVX2);
//   - the multipliers come back to their elements: a hanging rope's top
//     link carries the weight below it;
//   - the per-step factors a state keeps follow a new substep and a new
//     material: the rope's links stretch by compliance times their load.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <span>
#include <vector>

#include "support/xpbd_test.hpp"
#include "xpbd/distance_stream.hpp"
#include "xpbd/solve.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

Model cloth(int n, Real damping) {
  SceneDesc d;
  ClothGridDesc g;
  g.nx = g.ny = n;
  g.pins = ClothPins::top_corners;
  g.u = Vec3::UnitX();
  g.v = Vec3::UnitZ();
  g.stretch.compliance = Real(1e-6);
  g.stretch.damping = damping;
  add_cloth_grid(d, g);
  return compile(d);
}

// A rope of 11 particles of 0.2 kg, 0.1 m apart, pinned at the first,
// hanging along -y.
Model rope11(Real compliance, Real damping) {
  SceneDesc d;
  RopeDesc r;
  r.n = 11;
  r.spacing = Real(0.1);
  r.mass = Real(0.2);
  r.mat.compliance = compliance;
  r.mat.damping = damping;
  add_rope(d, r);
  return compile(d);
}

TEST(DistanceStream, HoldsTheColouredElementsAndFollowsSetMaterial) {
  Model m = cloth(12, 0);
  Material soft;
  soft.compliance = Real(3e-4);
  soft.damping = Real(0.5);
  set_material<Distance>(m, 10, 40, soft);
  const DistanceStream& ds = m.distance_stream;
  const auto& order = m.distance_colours.order;
  ASSERT_EQ(ds.size(), order.size());
  ASSERT_EQ(ds.size(), m.get<Distance>().size());
  int soft_seen = 0;
  for (std::size_t j = 0; j < ds.size(); ++j) {
    const Distance& c = m.get<Distance>()[std::size_t(order[j])];
    EXPECT_EQ(ds.a[j], c.p[0]) << j;
    EXPECT_EQ(ds.b[j], c.p[1]) << j;
    EXPECT_EQ(ds.rest[j], c.rest) << j;
    EXPECT_EQ(ds.compliance[j], c.mat.compliance) << j;
    EXPECT_EQ(ds.damping[j], c.mat.damping) << j;
    soft_seen += ds.compliance[j] == soft.compliance;
  }
  EXPECT_EQ(soft_seen, 40);
}

// set_simd_kernel takes the three names (and "auto") and refuses any
// other, and any kernel this build or CPU does not have, naming the value;
// the cap shows in simd_kernel() and distance_kernel() (the colours' and
// the levels') and is lifted again.
TEST(DistanceStream, KernelCapIsCheckedAndNamed) {
  const std::string widest = simd_kernel();
  for (const char* bad : {"avx1024", "", "AVX2"}) {
    try {
      set_simd_kernel(bad);
      ADD_FAILURE() << "accepted \"" << bad << "\"";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("\"") + bad + "\""), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(std::string(simd_kernel()), widest);
  if (widest != "avx512") {
    try {
      set_simd_kernel("avx512");
      ADD_FAILURE() << "accepted avx512 where the widest kernel is " << widest;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("not available"), std::string::npos) << e.what();
    }
  }
  {
    const test::KernelCap cap("scalar");
    EXPECT_STREQ(simd_kernel(), "scalar");
    EXPECT_STREQ(distance_kernel(), "scalar");
    EXPECT_STREQ(distance_kernel(true), "scalar");
  }
  EXPECT_EQ(std::string(simd_kernel()), widest);
  // The Distance sweep runs a named kernel ("avx512" in float, which has
  // no 512-bit Distance kernel, runs the 256-bit AVX-512 one, or AVX2
  // without AVX-512VL); by default ("auto") a vector kernel, the fastest
  // of them where the CPU has AVX-512.
  const std::vector<std::string> kernels = test::vector_kernels();
  const bool ymm = std::find(kernels.begin(), kernels.end(), "avx512-ymm") != kernels.end();
  for (const std::string& k : kernels) {
    const test::KernelCap cap(k);
    EXPECT_STREQ(simd_kernel(), k == "avx512-ymm" ? "avx512" : k.c_str());
    const std::string named = k == "avx512" && sizeof(Real) == sizeof(float) ? (ymm ? "avx512-ymm" : "avx2") : k;
    EXPECT_EQ(std::string(distance_kernel()), named);
    EXPECT_EQ(std::string(distance_kernel(true)), named);  // the levels' too: a named kernel is not measured
  }
  // By default the colours' and the levels' kernels are each measured
  // (on long and on short runs), so each may be any vector kernel.
  for (const bool levels : {false, true}) {
    const std::string d = distance_kernel(levels);
    if (widest == "avx512")
      EXPECT_TRUE(d == "avx2" || (d == "avx512" && sizeof(Real) == sizeof(double)) || (d == "avx512-ymm" && ymm))
          << d << (levels ? " (levels)" : "");
    else
      EXPECT_EQ(d, widest);
  }
  if (!ymm) {
    try {
      set_simd_kernel("avx512-ymm");
      ADD_FAILURE() << "accepted avx512-ymm without AVX-512VL";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("not available"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(set_simd_kernel("Auto"), ConfigError);
}

TEST(DistanceStream, UnpreparedStateAndBadSubstepAreNamed) {
  const Model m = cloth(6, 0);
  State s = make_state(m);
  SolveContext sc;
  sc.h = Real(0.01);
  sc.x = s.x.data();
  sc.inv_mass = m.inv_mass.data();
  try {
    project_stream(m, s, sc, true);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("prepare_stream"), std::string::npos) << e.what();
  }
  try {
    prepare_stream(m, s, Real(-1));
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("h must be"), std::string::npos) << e.what();
  }
  prepare_stream(m, s, sc.h);
  EXPECT_NO_THROW(project_stream(m, s, sc, true));
  // A stream without its inverse-mass sums (not made by compile) is named,
  // by prepare_stream and by a coloured step.
  Model bare = m;
  bare.distance_stream.inv_mass_sum.clear();
  try {
    prepare_stream(bare, s, sc.h);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("model.distance_stream.inv_mass_sum has 0 entries"), std::string::npos)
        << e.what();
  }
  StepConfig cfg;
  cfg.dt = Real(0.01);
  cfg.coloured = true;
  try {
    step(bare, s, cfg);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("StepConfig.coloured: model.distance_stream.inv_mass_sum"),
              std::string::npos)
        << e.what();
  }
}

// One sweep from a perturbed state: the stream kernel against the
// pair-distance kernel over distance_by_colour.
void check_one_sweep(Real damping, bool reverse, bool simd) {
  const Model m = cloth(24, damping);
  State a = make_state(m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<Real> u(Real(-0.01), Real(0.01));
  for (std::size_t i = 0; i < a.x.size(); ++i) {
    a.x_prev[i] = a.x[i];
    a.x[i] += Vec3(u(rng), u(rng), u(rng));
  }
  State b = a;
  SolveContext sc;
  sc.h = Real(1) / 600;
  sc.inv_mass = m.inv_mass.data();
  sc.reverse = reverse;
  sc.x = a.x.data();
  sc.x_prev = a.x_prev.data();
  sc.eval.x = a.x.data();
  const std::span<const Distance> by_colour(m.distance_by_colour);
  const std::span<const Index> order(m.distance_colours.order);
  if (damping > 0)
    project_all_coloured<Distance, true>(by_colour, order, std::span<Real>(a.lambdas<Distance>()), sc);
  else
    project_all_coloured<Distance, false>(by_colour, order, std::span<Real>(a.lambdas<Distance>()), sc);
  sc.x = b.x.data();
  sc.x_prev = b.x_prev.data();
  sc.eval.x = b.x.data();
  prepare_stream(m, b, sc.h);
  project_stream(m, b, sc, simd);

  Real moved = 0, worst = 0, lam_scale = 0, worst_lam = 0;
  for (std::size_t i = 0; i < a.x.size(); ++i) {
    moved = std::max(moved, (a.x[i] - a.x_prev[i]).norm());
    worst = std::max(worst, (a.x[i] - b.x[i]).norm());
  }
  for (std::size_t j = 0; j < order.size(); ++j) {
    const Real la = a.lambdas<Distance>()[std::size_t(order[j])];
    lam_scale = std::max(lam_scale, std::abs(la));
    worst_lam = std::max(worst_lam, std::abs(la - b.stream_lambda[j]));
  }
  EXPECT_GT(lam_scale, Real(0));
  // Round-off only: positions of order 1 m, a few operations per element.
  EXPECT_LE(worst, 64 * kEps) << "damping " << damping << " reverse " << reverse;
  EXPECT_LE(worst_lam, 1e3 * kEps * lam_scale) << "damping " << damping << " reverse " << reverse;
  EXPECT_GT(moved, Real(0.001));
}

TEST(DistanceStream, OneSweepIsThePairDistanceKernelsToRoundOff) {
  for (bool simd : {false, true}) {
    check_one_sweep(0, false, simd);
    check_one_sweep(0, true, simd);
    check_one_sweep(Real(2), false, simd);
    check_one_sweep(Real(2), true, simd);
  }
}

bool same_bits(const Vec3& p, const Vec3& q) { return std::memcmp(p.data(), q.data(), sizeof(Real) * 3) == 0; }

// Every vector kernel this CPU has (AVX-512 at 512 and 256 bits and AVX2,
// each named in turn) against the scalar one.
TEST(DistanceStream, VectorAndScalarKernelsGiveTheSameBits) {
  if (test::vector_kernels().empty()) GTEST_SKIP() << "this CPU has no vector kernel";
  for (const std::string& kernel : test::vector_kernels())
  for (Real damping : {Real(0), Real(2)}) {
    const test::KernelCap cap(kernel);
    ASSERT_EQ(std::string(simd_kernel()), kernel == "avx512-ymm" ? "avx512" : kernel);
    const Model m = cloth(48, damping);
    State vec = make_state(m);
    // A zero-length edge (particles 1 and 2 on top of each other): left alone by both kernels.
    vec.x[2] = vec.x[1];
    State sca = vec;
    StepConfig cfg;
    cfg.coloured = true;
    cfg.alternate_sweeps = true;
    cfg.iterations = 2;
    StepConfig scalar = cfg;
    scalar.simd = false;
    for (int k = 0; k < 30; ++k) {
      step(m, vec, cfg);
      step(m, sca, scalar);
    }
    Real moved = 0;
    int differ = 0;
    for (std::size_t i = 0; i < vec.x.size(); ++i) {
      differ += !same_bits(vec.x[i], sca.x[i]) || !same_bits(vec.v[i], sca.v[i]);
      moved = std::max(moved, (vec.x[i] - m.x0[i]).norm());
      ASSERT_TRUE(vec.x[i].allFinite()) << i;
    }
    EXPECT_EQ(differ, 0) << kernel << ", damping " << damping;
    EXPECT_EQ(std::memcmp(vec.lambdas<Distance>().data(), sca.lambdas<Distance>().data(),
                          sizeof(Real) * vec.lambdas<Distance>().size()),
              0)
        << kernel;
    EXPECT_GT(moved, Real(0.1));
  }
}

// A rope of 11 particles hanging from its pinned first one, settled with
// many iterations: the link at the pin carries the weight of the 10
// particles below it, |lambda| / h^2 = sum m g (within 1%). Read from
// State::lambda, which step() fills from the stream multipliers.
TEST(DistanceStream, MultipliersComeBackToTheirElements) {
  const Model m = rope11(Real(1e-7), Real(0.1));
  State s = make_state(m);
  StepConfig cfg;
  cfg.coloured = true;
  cfg.substeps = 4;
  cfg.iterations = 40;
  cfg.dt = Real(1) / 60;
  for (int k = 0; k < 300; ++k) step(m, s, cfg);
  Real below = 0;
  for (Real w : m.inv_mass)
    if (w > 0) below += 1 / w;
  const Real g = cfg.gravity.norm(), h = s.last_substep;
  const auto& links = m.get<Distance>();
  for (std::size_t k = 0; k < links.size(); ++k) {
    // Link k carries the particles k + 1 .. 10.
    const Real carried = below * Real(10 - k) / 10;
    EXPECT_NEAR(std::abs(s.lambdas<Distance>()[k]) / (h * h), carried * g, Real(0.01) * carried * g)
        << "link " << k;
  }
}


// The per-step factors (compliance/h^2 and the denominators) are kept from
// step to step (State::stream_factors) and must follow a new substep and a
// new material. Converged, each link of a rope obeys Hooke's law: its
// stretch is its compliance times its tension, lambda / h^2 (XPBD's
// C + alpha lambda / h^2 = 0); factors kept from another h or material would
// make it (h / h_old)^2 or alpha_old / alpha times that.
TEST(DistanceStream, KeptFactorsFollowTheSubstepAndTheMaterial) {
  Model m = rope11(Real(1e-3), 0);
  State s = make_state(m);
  StepConfig cfg;
  cfg.coloured = true;  // a rope's array order runs element by element, without the stream
  cfg.iterations = 40;
  cfg.dt = Real(1) / 60;
  const auto hooke = [&](Real compliance, const char* when) {
    const Real h = s.last_substep;
    const auto& links = m.get<Distance>();
    for (std::size_t k = 0; k < links.size(); ++k) {
      const Real len = (s.x[std::size_t(links[k].p[0])] - s.x[std::size_t(links[k].p[1])]).norm();
      const Real tension = std::abs(s.lambdas<Distance>()[k]) / (h * h);
      EXPECT_GT(tension, Real(0.1)) << when << ", link " << k;  // it carries at least one particle
      EXPECT_NEAR(len - links[k].rest, compliance * tension, Real(0.01) * compliance * tension)
          << when << ", link " << k;
    }
  };
  cfg.substeps = 4;
  for (int k = 0; k < 60; ++k) step(m, s, cfg);
  hooke(Real(1e-3), "4 substeps");
  EXPECT_EQ(s.stream_factors.h, cfg.dt / Real(4));
  cfg.substeps = 9;
  for (int k = 0; k < 3; ++k) step(m, s, cfg);
  hooke(Real(1e-3), "9 substeps after 4");
  EXPECT_EQ(s.stream_factors.h, cfg.dt / Real(9));
  Material softer;
  softer.compliance = Real(3e-3);
  set_material<Distance>(m, softer);
  for (int k = 0; k < 3; ++k) step(m, s, cfg);
  hooke(Real(3e-3), "a softer material set after the steps");
}

// The same over the array order's levels (a cloth: a rope's array order
// does not use them): after a new substep and a new material, a state that
// kept its factors steps to the same bits as one made to compute them again.
TEST(DistanceStream, KeptFactorsOfTheLevelsAreThoseComputedAgain) {
  Model m = cloth(16, Real(0.05));
  State s = make_state(m);
  StepConfig cfg;
  cfg.dt = Real(1) / 60;
  cfg.substeps = 4;
  for (int k = 0; k < 5; ++k) step(m, s, cfg);
  ASSERT_EQ(s.stream_factors.h, cfg.dt / Real(4)) << "the array order did not run over its levels";
  const auto again = [&](const char* when) {
    State fresh = s;
    fresh.stream_factors = {};
    step(m, s, cfg);
    step(m, fresh, cfg);
    ASSERT_EQ(s.x.size(), fresh.x.size());
    EXPECT_EQ(std::memcmp(s.x.data(), fresh.x.data(), s.x.size() * sizeof(Vec3)), 0) << when;
  };
  cfg.substeps = 7;
  again("7 substeps after 4");
  EXPECT_EQ(s.stream_factors.h, cfg.dt / Real(7));
  Material softer;
  softer.compliance = Real(1e-3);
  set_material<Distance>(m, 0, 100, softer);
  again("a softer material on 100 elements");
  again("the step after");
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
