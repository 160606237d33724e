// The compiled coloured Tether sweep (Model::tether_stream,
// xpbd/src/tether_kernel.hpp): what step() runs for Tether elements with
// StepConfig::coloured in XPBD.
//   - the schedule lets a colour share only particles of inverse mass 0 (a
//     cloth tethered to its two pins needs two colours), and the stream
//     follows set_material;
//   - two sweeps compute what the pair-distance kernel computes over the
//     same elements in the same order (solve.hpp), to round-off: undamped,
//     damped, reversed, with slack and stretched tethers and taut ones
//     that go slack;
//   - the AVX2 and the scalar kernel give the same bits over 30 steps, with
//     batches that mix moving and kinematic particles on one side; so do 1
//     and 2 threads;
//   - the multipliers come back to their elements: weights hanging from one
//     pinned anchor by tethers alone give |lambda| / h^2 = m g.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <span>
#include <vector>

#include "support/xpbd_test.hpp"
#include "xpbd/distance_stream.hpp"
#include "xpbd/solve.hpp"
#include "xpbd/workers.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

// An n x n cloth in the x-z plane pinned at its two top corners, a tether
// from every movable particle to each pin (straight-line lengths), soft
// edges so that the tethers carry the load. `extra`: tethers whose anchor
// moves (between free particles) and one from a pinned particle to a free
// one, so that some vector batches mix moving and kinematic particles.
SceneDesc tethered_cloth(int n, Real damping, bool extra) {
  SceneDesc d;
  ClothGridDesc g;
  g.nx = g.ny = n;
  g.pins = ClothPins::top_corners;
  g.u = Vec3::UnitX();
  g.v = Vec3::UnitZ();
  g.stretch.compliance = Real(1e-4);
  g.tethers = TetherAnchors::all_pinned;
  g.tether_metric = TetherMetric::euclidean;
  g.tether_mat.damping = damping;
  add_cloth_grid(d, g);
  if (extra) {
    const Index last = Index(n * n - 1);
    for (Index i = Index(n); i + Index(n) <= last; i += 3) {
      TetherDesc t;
      t.particle = i;
      t.anchor = i + Index(n) - 1;
      t.mat.damping = damping;
      d.tethers.push_back(t);
    }
    TetherDesc t;  // particle 0 is pinned: its side of the element never moves
    t.particle = 0;
    t.anchor = Index(n + 1);
    d.tethers.push_back(t);
  }
  return d;
}

// Every element in exactly one colour, and no particle of inverse mass > 0
// twice in a colour.
void expect_valid_schedule(const Model& m) {
  const ColourSchedule& cs = m.tether_colours;
  std::vector<int> seen(m.get<Tether>().size(), 0);
  for (Index c = 0; c < cs.num_colours(); ++c) {
    std::set<Index> moving;
    for (Index j = cs.begin[std::size_t(c)]; j < cs.begin[std::size_t(c) + 1]; ++j) {
      const Index k = cs.order[std::size_t(j)];
      ++seen[std::size_t(k)];
      for (Index p : m.get<Tether>()[std::size_t(k)].p) {
        if (m.inv_mass[std::size_t(p)] > 0) {
          EXPECT_TRUE(moving.insert(p).second) << "colour " << c << " particle " << p;
        }
      }
    }
  }
  for (std::size_t k = 0; k < seen.size(); ++k) EXPECT_EQ(seen[k], 1) << k;
}

TEST(TetherStream, ColoursShareOnlyKinematicParticlesAndFollowSetMaterial) {
  Model m = compile(tethered_cloth(10, 0, false));
  const ColourSchedule& cs = m.tether_colours;
  const auto& t = m.get<Tether>();
  ASSERT_EQ(t.size(), std::size_t(2 * (100 - 2)));
  // Every movable particle has one tether per pin; the pins never move:
  // two colours, whatever the cloth's size.
  EXPECT_EQ(cs.num_colours(), 2);
  expect_valid_schedule(m);
  // With tethers between free particles too, those share no particle in a
  // colour, and take more colours.
  const Model x = compile(tethered_cloth(10, 0, true));
  expect_valid_schedule(x);
  EXPECT_GT(x.tether_colours.num_colours(), 2);

  Material soft;
  soft.compliance = Real(2e-3);
  soft.damping = Real(0.25);
  set_material<Tether>(m, 5, 30, soft);
  const DistanceStream& ts = m.tether_stream;
  ASSERT_EQ(ts.size(), t.size());
  int soft_seen = 0;
  for (std::size_t j = 0; j < ts.size(); ++j) {
    const Tether& e = t[std::size_t(cs.order[j])];
    EXPECT_EQ(ts.a[j], e.p[0]) << j;
    EXPECT_EQ(ts.b[j], e.p[1]) << j;
    EXPECT_EQ(ts.rest[j], e.length) << j;
    EXPECT_EQ(ts.compliance[j], e.mat.compliance) << j;
    EXPECT_EQ(ts.damping[j], e.mat.damping) << j;
    soft_seen += ts.damping[j] == soft.damping;
  }
  EXPECT_EQ(soft_seen, 30);
}

// Two sweeps from a perturbed state (about half the tethers stretched, the
// rest slack), the particles moved again between them, so that some taut
// tethers go slack and must let go (their multiplier clamped at 0): the
// stream kernel against the pair-distance kernel over the elements copied
// in schedule order.
void check_two_sweeps(Real damping, bool reverse, bool simd) {
  const Model m = compile(tethered_cloth(24, damping, true));
  State a = make_state(m);
  std::mt19937 rng(11);
  std::uniform_real_distribution<Real> u(Real(-0.02), Real(0.02));
  auto shake = [&](State& s) {
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (m.inv_mass[i] > 0) s.x[i] += Vec3(u(rng), u(rng), u(rng));
  };
  a.x_prev = a.x;
  shake(a);
  State b = a;
  SolveContext sc;
  sc.h = Real(1) / 600;
  sc.inv_mass = m.inv_mass.data();
  sc.reverse = reverse;
  std::vector<Tether> by_colour;
  for (Index k : m.tether_colours.order) by_colour.push_back(m.get<Tether>()[std::size_t(k)]);
  const std::span<const Index> order(m.tether_colours.order);
  auto reference_sweep = [&] {
    sc.x = a.x.data();
    sc.x_prev = a.x_prev.data();
    sc.eval.x = a.x.data();
    if (damping > 0)
      project_all_coloured<Tether, true>(by_colour, order, std::span<Real>(a.lambdas<Tether>()), sc);
    else
      project_all_coloured<Tether, false>(by_colour, order, std::span<Real>(a.lambdas<Tether>()), sc);
  };
  auto stream_sweep = [&] {
    sc.x = b.x.data();
    sc.x_prev = b.x_prev.data();
    sc.eval.x = b.x.data();
    project_tether_stream(m, b, sc, simd);
  };
  prepare_stream(m, b, sc.h);
  reference_sweep();
  stream_sweep();
  const std::vector<Real> first = a.lambdas<Tether>();
  int taut = 0;
  for (Real l : first) taut += l != 0;
  const std::vector<Vec3> before = a.x;
  shake(a);
  for (std::size_t i = 0; i < a.x.size(); ++i) b.x[i] += a.x[i] - before[i];
  reference_sweep();
  stream_sweep();

  Real worst = 0, lam_scale = 0, worst_lam = 0;
  int released = 0;
  for (std::size_t i = 0; i < a.x.size(); ++i) worst = std::max(worst, (a.x[i] - b.x[i]).norm());
  for (std::size_t j = 0; j < order.size(); ++j) {
    const Real la = a.lambdas<Tether>()[std::size_t(order[j])];
    lam_scale = std::max(lam_scale, std::abs(la));
    worst_lam = std::max(worst_lam, std::abs(la - b.tether_lambda[j]));
  }
  for (std::size_t k = 0; k < first.size(); ++k) released += first[k] != 0 && a.lambdas<Tether>()[k] == 0;
  EXPECT_GT(taut, int(order.size() / 4)) << "stretched tethers";
  EXPECT_GT(released, taut / 10) << "taut tethers that let go";
  EXPECT_LE(worst, 64 * kEps) << "damping " << damping << " reverse " << reverse << " simd " << simd;
  EXPECT_LE(worst_lam, 1e3 * kEps * lam_scale) << "damping " << damping << " reverse " << reverse;
}

TEST(TetherStream, TwoSweepsAreThePairDistanceKernelsToRoundOff) {
  for (bool simd : {false, true}) {
    check_two_sweeps(0, false, simd);
    check_two_sweeps(0, true, simd);
    check_two_sweeps(Real(2), false, simd);
    check_two_sweeps(Real(2), true, simd);
  }
}

bool same_bits(const std::vector<Vec3>& p, const std::vector<Vec3>& q) {
  return p.size() == q.size() && std::memcmp(p.data(), q.data(), sizeof(Vec3) * p.size()) == 0;
}
bool same_bits(const std::vector<Real>& p, const std::vector<Real>& q) {
  return p.size() == q.size() && std::memcmp(p.data(), q.data(), sizeof(Real) * p.size()) == 0;
}

// Every vector kernel this CPU has (each set as the cap in turn; the
// widest alone, scalar against threaded, where it has none).
TEST(TetherStream, VectorScalarAndThreadedStepsGiveTheSameBits) {
  std::vector<std::string> kernels = test::vector_kernels();
  const bool vector = !kernels.empty();
  if (!vector) kernels = {"scalar"};
  Workers two(2);
  for (const std::string& kernel : kernels)
  for (Real damping : {Real(0), Real(2)}) {
    const test::KernelCap cap(kernel);
    const Model m = compile(tethered_cloth(40, damping, true));
    State vec = make_state(m);
    State sca = vec, thr = vec;
    StepConfig cfg;
    cfg.coloured = true;
    cfg.alternate_sweeps = true;
    cfg.iterations = 2;
    StepConfig scalar = cfg, threaded = cfg;
    scalar.simd = false;
    threaded.workers = &two;
    for (int k = 0; k < 30; ++k) {
      step(m, vec, cfg);
      step(m, sca, scalar);
      step(m, thr, threaded);
    }
    ASSERT_TRUE(test::all_finite(vec));
    Real moved = 0;
    for (std::size_t i = 0; i < vec.x.size(); ++i) moved = std::max(moved, (vec.x[i] - m.x0[i]).norm());
    EXPECT_GT(moved, Real(0.1));
    Real tension = 0;
    for (Real l : vec.lambdas<Tether>()) tension = std::max(tension, std::abs(l));
    EXPECT_GT(tension, Real(0)) << "no tether was ever taut";
    EXPECT_TRUE(same_bits(vec.x, thr.x) && same_bits(vec.v, thr.v)) << kernel << ", damping " << damping;
    EXPECT_TRUE(same_bits(vec.lambdas<Tether>(), thr.lambdas<Tether>())) << kernel << ", damping " << damping;
    if (vector) {
      EXPECT_TRUE(same_bits(vec.x, sca.x) && same_bits(vec.v, sca.v)) << kernel << ", damping " << damping;
      EXPECT_TRUE(same_bits(vec.lambdas<Tether>(), sca.lambdas<Tether>())) << kernel << ", damping " << damping;
    }
  }
}

// Weights hanging straight down from one pinned anchor by rigid tethers
// alone (lengths 0.1 .. 0.1 n m, masses 0.1 .. 0.1 n kg), started at rest
// at their lengths: every substep gravity stretches each tether by g h^2
// and its projection takes it back, so |lambda| / h^2 = m g and the weights
// stay where they are, to the round-off of positions of length L (the
// stretch is L - length). All tethers share the anchor, so they are one
// colour, projected 4 or 8 at a time.
TEST(TetherStream, MultipliersComeBackToTheirElements) {
  SceneDesc d;
  const Real g = Real(9.81);
  d.add_particle(Vec3::Zero(), 0);
  const int n = 19;
  for (int i = 1; i <= n; ++i) {
    d.add_particle(Vec3(0, -Real(0.1) * Real(i), 0), Real(0.1) * Real(i));
    TetherDesc t;
    t.particle = Index(i);
    t.anchor = 0;
    d.tethers.push_back(t);
  }
  const Model m = compile(d);
  ASSERT_EQ(m.tether_colours.num_colours(), 1);
  State s = make_state(m);
  StepConfig cfg;
  cfg.coloured = true;
  cfg.substeps = 10;
  for (int k = 0; k < 5; ++k) step(m, s, cfg);
  const Real h = cfg.dt / Real(cfg.substeps);
  for (int i = 1; i <= n; ++i) {
    const Real mass = Real(0.1) * Real(i), length = Real(0.1) * Real(i);
    const Real force = std::abs(s.lambdas<Tether>()[std::size_t(i - 1)]) / (h * h);
    EXPECT_NEAR(force, mass * g, 16 * kEps * length * mass / (h * h)) << "weight " << i;
    EXPECT_NEAR(s.x[std::size_t(i)].y(), -length, 16 * kEps * length) << "weight " << i;
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
