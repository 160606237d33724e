// The compiled coloured DihedralBending sweep (dihedral_stream.hpp): what
// step() runs for the hinges with StepConfig::coloured in XPBD.
//   - Model::dihedral_colours is a colouring (every hinge once, no two
//     hinges of a colour share a particle) and Model::dihedral_stream holds
//     the hinges in that order and follows set_material;
//   - one sweep of the stream kernel computes what the written-out dihedral
//     kernel (solve_dihedral.hpp) computes over the same hinges in the same
//     order, to round-off: undamped, damped, reversed, scalar and AVX2;
//   - the AVX2 and the scalar kernel give the same results bit for bit over
//     30 steps of a falling bending cloth with a degenerate hinge (skipped
//     on a CPU without AVX2);
//   - step() returns the multipliers to their elements;
//   - an unprepared state is named.
// (The physics of the coloured hinge sweep is tested by
// tests/validation/test_dihedral_bending_rest.cpp, which runs both orders;
// threads by tests/unit/test_workers.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "support/xpbd_test.hpp"
#include "xpbd/dihedral_stream.hpp"
#include "xpbd/distance_stream.hpp"
#include "xpbd/solve.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

Model bending_cloth(int n, Real damping) {
  SceneDesc d;
  ClothGridDesc g;
  g.nx = g.ny = n;
  g.pins = ClothPins::top_corners;
  g.u = Vec3::UnitX();
  g.v = Vec3::UnitZ();
  g.stretch.compliance = Real(1e-6);
  g.set_bending(ClothBending::dihedral, Material{Real(1e-4), damping, 1});
  add_cloth_grid(d, g);
  return compile(d);
}

TEST(DihedralStream, IsAColouringAndFollowsSetMaterial) {
  Model m = bending_cloth(12, 0);
  const auto& hs = m.get<DihedralBending>();
  const ColourSchedule& cs = m.dihedral_colours;
  ASSERT_GT(hs.size(), 100u);
  ASSERT_EQ(cs.order.size(), hs.size());
  ASSERT_EQ(std::size_t(cs.begin.back()), hs.size());
  std::vector<int> seen(hs.size(), 0);
  for (Index c = 0; c < cs.num_colours(); ++c) {
    std::set<Index> particles;
    for (Index j = cs.begin[std::size_t(c)]; j < cs.begin[std::size_t(c) + 1]; ++j) {
      const Index k = cs.order[std::size_t(j)];
      ++seen[std::size_t(k)];
      for (Index p : hs[std::size_t(k)].p) EXPECT_TRUE(particles.insert(p).second) << "colour " << c << " hinge " << k;
    }
  }
  for (std::size_t k = 0; k < seen.size(); ++k) EXPECT_EQ(seen[k], 1) << k;

  Material soft{Real(3e-2), Real(0.5), 1};
  set_material<DihedralBending>(m, 10, 40, soft);
  const DihedralStream& ds = m.dihedral_stream;
  ASSERT_EQ(ds.size(), hs.size());
  int soft_seen = 0;
  for (std::size_t j = 0; j < ds.size(); ++j) {
    const DihedralBending& c = hs[std::size_t(cs.order[j])];
    EXPECT_EQ(ds.p0[j], c.p[0]);
    EXPECT_EQ(ds.p1[j], c.p[1]);
    EXPECT_EQ(ds.p2[j], c.p[2]);
    EXPECT_EQ(ds.p3[j], c.p[3]);
    EXPECT_EQ(ds.rest[j], c.rest_angle);
    EXPECT_EQ(ds.compliance[j], c.mat.compliance);
    EXPECT_EQ(ds.damping[j], c.mat.damping);
    soft_seen += ds.compliance[j] == soft.compliance;
  }
  EXPECT_EQ(soft_seen, 40);
}

TEST(DihedralStream, UnpreparedStateIsNamed) {
  const Model m = bending_cloth(6, 0);
  State s = make_state(m);
  SolveContext sc;
  sc.h = Real(0.01);
  sc.x = s.x.data();
  sc.inv_mass = m.inv_mass.data();
  try {
    project_dihedral_stream(m, s, sc, true);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("prepare_stream"), std::string::npos) << e.what();
  }
  prepare_stream(m, s, sc.h);
  EXPECT_NO_THROW(project_dihedral_stream(m, s, sc, true));
}

// One sweep from a crumpled state: the stream kernel against the
// written-out kernel over the hinges copied in schedule order.
void check_one_sweep(Real damping, bool reverse, bool simd) {
  const Model m = bending_cloth(24, damping);
  State a = make_state(m);
  std::mt19937 rng(11);
  std::uniform_real_distribution<Real> u(Real(-0.01), Real(0.01));  // spacing 0.043 m: hinges bent by up to ~40 deg
  for (std::size_t i = 0; i < a.x.size(); ++i) {
    a.x_prev[i] = a.x[i];
    a.x[i] += Vec3(u(rng), u(rng), u(rng));
  }
  State b = a;
  const std::vector<Vec3> before = a.x;
  std::vector<DihedralBending> by_colour;
  for (Index k : m.dihedral_colours.order) by_colour.push_back(m.get<DihedralBending>()[std::size_t(k)]);
  std::vector<Real> lambda(by_colour.size(), Real(0));
  SolveContext sc;
  sc.h = Real(1) / 600;
  sc.inv_mass = m.inv_mass.data();
  sc.reverse = reverse;
  sc.x = a.x.data();
  sc.x_prev = a.x_prev.data();
  sc.eval.x = a.x.data();
  if (damping > 0)
    project_all<DihedralBending, true>(std::span<const DihedralBending>(by_colour), std::span<Real>(lambda), sc);
  else
    project_all<DihedralBending, false>(std::span<const DihedralBending>(by_colour), std::span<Real>(lambda), sc);
  sc.x = b.x.data();
  sc.x_prev = b.x_prev.data();
  sc.eval.x = b.x.data();
  prepare_stream(m, b, sc.h);
  project_dihedral_stream(m, b, sc, simd);

  Real moved = 0, worst = 0, lam_scale = 0, worst_lam = 0;
  for (std::size_t i = 0; i < a.x.size(); ++i) {
    moved = std::max(moved, (a.x[i] - before[i]).norm());
    worst = std::max(worst, (a.x[i] - b.x[i]).norm());
  }
  for (std::size_t j = 0; j < lambda.size(); ++j) {
    lam_scale = std::max(lam_scale, std::abs(lambda[j]));
    worst_lam = std::max(worst_lam, std::abs(lambda[j] - b.dihedral_lambda[j]));
  }
  EXPECT_GT(lam_scale, Real(0));
  // Round-off only. The angle's error is a few eps (rad) times the
  // condition of atan2 near the hinges' angles; a correction is the angle
  // over sum w|g|^2 times a gradient of order 1/height (about 20 1/m), so
  // position errors of order eps * 1 m, and the chain of corrections through
  // shared particles multiplies them by the number of colours at most.
  EXPECT_LE(worst, 64 * kEps) << "damping " << damping << " reverse " << reverse << " simd " << simd;
  EXPECT_LE(worst_lam, 64 * kEps * lam_scale)
      << "damping " << damping << " reverse " << reverse << " simd " << simd;
  EXPECT_GT(moved, Real(1e-4));  // the sweep did bend the hinges back
}

TEST(DihedralStream, OneSweepIsTheWrittenOutKernelsToRoundOff) {
  for (bool simd : {false, true}) {
    check_one_sweep(0, false, simd);
    check_one_sweep(0, true, simd);
    check_one_sweep(Real(0.5), false, simd);
    check_one_sweep(Real(0.5), true, simd);
  }
}

bool same_bits(const Vec3& p, const Vec3& q) { return std::memcmp(p.data(), q.data(), sizeof(Real) * 3) == 0; }

// Every vector kernel this CPU has (AVX-512 and AVX2, each set as the cap
// in turn) against the scalar one.
TEST(DihedralStream, VectorAndScalarKernelsGiveTheSameBits) {
  if (test::vector_kernels().empty()) GTEST_SKIP() << "this CPU has no vector kernel";
  for (const std::string& kernel : test::vector_kernels())
  for (Real damping : {Real(0), Real(0.5)}) {
    const test::KernelCap cap(kernel);
    const Model m = bending_cloth(40, damping);
    State vec = make_state(m);
    // Particles 1 and 2 on top of each other: the hinges that have both are
    // degenerate and left alone by both kernels.
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
    const auto& lv = vec.lambdas<DihedralBending>();
    const auto& ls = sca.lambdas<DihedralBending>();
    ASSERT_EQ(lv.size(), ls.size());
    EXPECT_EQ(std::memcmp(lv.data(), ls.data(), sizeof(Real) * lv.size()), 0) << kernel;
    EXPECT_GT(moved, Real(0.1));
  }
}

TEST(DihedralStream, StepReturnsTheMultipliersToTheirElements) {
  const Model m = bending_cloth(16, 0);
  State s = make_state(m);
  StepConfig cfg;
  cfg.coloured = true;
  for (int k = 0; k < 10; ++k) step(m, s, cfg);
  const auto& order = m.dihedral_colours.order;
  const auto& lambda = s.lambdas<DihedralBending>();
  int nonzero = 0;
  for (std::size_t j = 0; j < order.size(); ++j) {
    EXPECT_EQ(lambda[std::size_t(order[j])], s.dihedral_lambda[j]) << j;
    nonzero += lambda[std::size_t(order[j])] != Real(0);
  }
  EXPECT_GT(nonzero, int(order.size()) / 2);  // the falling cloth bends
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
