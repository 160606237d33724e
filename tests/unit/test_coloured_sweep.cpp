// Coloured sweep of the Distance elements (StepConfig::coloured).
//
// compile() colours the Distance elements greedily in array order
// (Model::distance_colours); step() with coloured = true projects them colour
// by colour: in XPBD over their compiled stream (Model::distance_stream,
// distance_stream.hpp), in PBD with the pair-distance kernel over a copy of
// the elements in schedule order (Model::distance_by_colour; solve.hpp,
// project_all_coloured). Checked here:
//   - the schedule is a permutation of the elements, no colour holds two
//     elements sharing a particle, each colour keeps array order, on the
//     builders' cloth, rope and tet box, and the exact greedy colouring of
//     small hand-made graphs;
//   - the coloured kernel computes what the array-order pair-distance kernel
//     computes when run over the elements in schedule order (same lambda per
//     element), for every variant (XPBD, damped, PBD) and reversed;
//   - physics with coloured on: the hanging chain of docs/design.md section 6
//     settles to the closed-form stretch, and a Fig. 5-like hanging cloth
//     follows the array-order cloth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <span>
#include <vector>

#include "support/xpbd_test.hpp"
#include "xpbd/distance_stream.hpp"
#include "xpbd/solve.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

// ---------------------------------------------------------------------------
// Schedule structure.

// The schedule is a valid colouring of `m`'s Distance elements: a
// permutation, no shared particle within a colour, array order within a
// colour, and no empty colour. Returns the number of colours.
Index check_schedule(const Model& m) {
  const auto& cs = m.get<Distance>();
  const ColourSchedule& sch = m.distance_colours;
  EXPECT_EQ(sch.order.size(), cs.size());
  EXPECT_FALSE(sch.begin.empty());
  if (sch.begin.empty()) return 0;
  EXPECT_EQ(sch.begin.front(), 0);
  EXPECT_EQ(static_cast<std::size_t>(sch.begin.back()), cs.size());
  std::vector<int> seen(cs.size(), 0);
  for (Index k : sch.order) {
    EXPECT_TRUE(k >= 0 && static_cast<std::size_t>(k) < cs.size()) << k;
    if (k >= 0 && static_cast<std::size_t>(k) < cs.size()) ++seen[static_cast<std::size_t>(k)];
  }
  for (std::size_t k = 0; k < cs.size(); ++k) EXPECT_EQ(seen[k], 1) << "element " << k;
  for (Index c = 0; c < sch.num_colours(); ++c) {
    const Index b = sch.begin[std::size_t(c)], e = sch.begin[std::size_t(c) + 1];
    EXPECT_LT(b, e) << "colour " << c << " is empty";
    std::set<Index> particles;
    for (Index j = b; j < e; ++j) {
      const Distance& d = cs[std::size_t(sch.order[std::size_t(j)])];
      EXPECT_TRUE(particles.insert(d.p[0]).second) << "colour " << c << " particle " << d.p[0];
      EXPECT_TRUE(particles.insert(d.p[1]).second) << "colour " << c << " particle " << d.p[1];
      if (j > b) {
        EXPECT_LT(sch.order[std::size_t(j) - 1], sch.order[std::size_t(j)]);
      }
    }
  }
  return sch.num_colours();
}

// Greedy colouring also never needs more colours than the largest number of
// elements at one particle (its degree) times 2, minus 1: an element sees at
// most deg(a) - 1 + deg(b) - 1 taken colours.
Index max_degree(const Model& m) {
  std::vector<Index> deg(std::size_t(m.num_particles()), 0);
  for (const Distance& d : m.get<Distance>()) {
    ++deg[std::size_t(d.p[0])];
    ++deg[std::size_t(d.p[1])];
  }
  return *std::max_element(deg.begin(), deg.end());
}

TEST(ColourSchedule, ClothGrid) {
  SceneDesc sd;
  ClothGridDesc d;
  d.nx = 13;
  d.ny = 9;
  d.pinned = {{0, 0}, {12, 0}};
  add_cloth_grid(sd, d);
  const Model m = compile(sd);
  const Index colours = check_schedule(m);
  // Interior particles have 4 structural, 4 shear and 4 bending edges: a
  // colouring needs at least 12 colours (all edges at one particle differ).
  EXPECT_EQ(max_degree(m), 12);
  EXPECT_GE(colours, 12);
  EXPECT_LE(colours, 2 * 12 - 1);
  std::printf("cloth 13 x 9: %zu edges, %d colours\n", m.get<Distance>().size(), int(colours));
}

TEST(ColourSchedule, Rope) {
  SceneDesc sd;
  RopeDesc r;
  r.n = 11;
  add_rope(sd, r);
  const Model m = compile(sd);
  // A path colours alternately: links 0, 2, 4, ... then 1, 3, 5, ...
  EXPECT_EQ(check_schedule(m), 2);
  EXPECT_EQ(m.distance_colours.order, (std::vector<Index>{0, 2, 4, 6, 8, 1, 3, 5, 7, 9}));
  EXPECT_EQ(m.distance_colours.begin, (std::vector<Index>{0, 5, 10}));
}

TEST(ColourSchedule, TetBox) {
  SceneDesc sd;
  TetBoxDesc t;
  t.nx = 3;
  t.ny = 2;
  t.nz = 2;
  add_tet_box(sd, t);
  const Model m = compile(sd);
  ASSERT_FALSE(m.get<Distance>().empty());
  const Index colours = check_schedule(m);
  EXPECT_GE(colours, max_degree(m));
  EXPECT_LE(colours, 2 * max_degree(m) - 1);
}

// Hand-made graphs whose greedy colouring in array order is worked out by
// hand (each element takes the smallest colour its two particles lack).
Model graph(int particles, const std::vector<std::pair<int, int>>& edges) {
  SceneDesc sd;
  for (int i = 0; i < particles; ++i)
    sd.add_particle(Vec3(Real(i), Real(i % 3), Real(i % 2)), Real(1));
  for (auto [a, b] : edges) sd.distances.push_back(DistanceDesc{a, b, Real(1), Material{}});
  return compile(sd);
}

TEST(ColourSchedule, HandMadeGraphs) {
  // Triangle: every pair of edges shares a particle, 3 colours.
  {
    const Model m = graph(3, {{0, 1}, {1, 2}, {2, 0}});
    EXPECT_EQ(check_schedule(m), 3);
    EXPECT_EQ(m.distance_colours.order, (std::vector<Index>{0, 1, 2}));
  }
  // Star with 5 spokes: 5 colours, one edge each.
  {
    const Model m = graph(6, {{0, 1}, {0, 2}, {3, 0}, {0, 4}, {5, 0}});
    EXPECT_EQ(check_schedule(m), 5);
  }
  // 4-cycle listed as two opposite edges first: e0 = 0-1 -> 0, e1 = 2-3 -> 0,
  // e2 = 1-2 -> 1, e3 = 3-0 -> 1.
  {
    const Model m = graph(4, {{0, 1}, {2, 3}, {1, 2}, {3, 0}});
    EXPECT_EQ(check_schedule(m), 2);
    EXPECT_EQ(m.distance_colours.order, (std::vector<Index>{0, 1, 2, 3}));
    EXPECT_EQ(m.distance_colours.begin, (std::vector<Index>{0, 2, 4}));
  }
  // A path 0-1-2-3-4-5 listed so that greedy needs 3 colours where 2 would
  // do: e0 = 0-1 -> 0, e1 = 3-4 -> 0, e2 = 1-2 -> 1, e3 = 4-5 -> 1,
  // e4 = 2-3: particle 2 has {1}, particle 3 has {0} -> 2.
  {
    const Model m = graph(6, {{0, 1}, {3, 4}, {1, 2}, {4, 5}, {2, 3}});
    EXPECT_EQ(check_schedule(m), 3);
    EXPECT_EQ(m.distance_colours.order, (std::vector<Index>{0, 1, 2, 3, 4}));
    EXPECT_EQ(m.distance_colours.begin, (std::vector<Index>{0, 2, 4, 5}));
  }
  // No Distance elements: no colours.
  {
    const Model m = graph(2, {});
    EXPECT_EQ(m.distance_colours.num_colours(), 0);
    EXPECT_TRUE(m.distance_colours.order.empty());
  }
}

// ---------------------------------------------------------------------------
// The coloured kernel against the array-order kernel over the permuted array.

enum class Variant { xpbd, damped, pbd };

struct Sweep {
  std::vector<Vec3> x;
  std::vector<Real> lambda;  // per element (model order)
};

SolveContext context(const Model& m, std::vector<Vec3>& x, const std::vector<Vec3>& x_prev,
                     Variant v) {
  SolveContext sc;
  sc.x = x.data();
  sc.x_prev = x_prev.data();
  sc.inv_mass = m.inv_mass.data();
  sc.h = Real(1) / Real(600);
  sc.method = v == Variant::pbd ? Method::pbd : Method::xpbd;
  sc.eval.x = x.data();
  return sc;
}

// `sweeps` coloured sweeps (alternating direction if `alternate`).
Sweep coloured(const Model& m, const std::vector<Vec3>& x0, const std::vector<Vec3>& x_prev,
               Variant v, int sweeps, bool alternate) {
  Sweep r{x0, std::vector<Real>(m.get<Distance>().size(), Real(0))};
  SolveContext sc = context(m, r.x, x_prev, v);
  const std::span<const Distance> by_colour(m.distance_by_colour);
  const std::span<const Index> order(m.distance_colours.order);
  for (int i = 0; i < sweeps; ++i) {
    sc.reverse = alternate && (i & 1) != 0;
    if (v == Variant::damped)
      project_all_coloured<Distance, true>(by_colour, order, r.lambda, sc);
    else
      project_all_coloured<Distance, false>(by_colour, order, r.lambda, sc);
  }
  return r;
}

// The reference: the elements copied in schedule order (colours last to
// first for a reversed sweep; inside a colour the order does not matter) and
// projected by the array-order kernel; lambda mapped back to elements.
Sweep reference(const Model& m, const std::vector<Vec3>& x0, const std::vector<Vec3>& x_prev,
                Variant v, int sweeps, bool alternate) {
  const auto& cs = m.get<Distance>();
  const ColourSchedule& sch = m.distance_colours;
  std::vector<Index> fwd, bwd;  // element of each position in the two orders
  for (Index c = 0; c < sch.num_colours(); ++c)
    for (Index j = sch.begin[std::size_t(c)]; j < sch.begin[std::size_t(c) + 1]; ++j)
      fwd.push_back(sch.order[std::size_t(j)]);
  for (Index c = sch.num_colours() - 1; c >= 0; --c)
    for (Index j = sch.begin[std::size_t(c)]; j < sch.begin[std::size_t(c) + 1]; ++j)
      bwd.push_back(sch.order[std::size_t(j)]);
  Sweep r{x0, std::vector<Real>(cs.size(), Real(0))};
  SolveContext sc = context(m, r.x, x_prev, v);
  for (int i = 0; i < sweeps; ++i) {
    const std::vector<Index>& ord = alternate && (i & 1) != 0 ? bwd : fwd;
    std::vector<Distance> perm;
    std::vector<Real> lam;
    for (Index k : ord) {
      perm.push_back(cs[std::size_t(k)]);
      lam.push_back(r.lambda[std::size_t(k)]);
    }
    if (v == Variant::damped)
      project_all<Distance, true>(std::span<const Distance>(perm), std::span<Real>(lam), sc);
    else
      project_all<Distance, false>(std::span<const Distance>(perm), std::span<Real>(lam), sc);
    for (std::size_t j = 0; j < ord.size(); ++j) r.lambda[std::size_t(ord[j])] = lam[j];
  }
  return r;
}

// The array-order kernel itself (to show the coloured order is a different
// Gauss-Seidel order, so the comparison above is not trivially satisfied).
Sweep array_order(const Model& m, const std::vector<Vec3>& x0, const std::vector<Vec3>& x_prev,
                  Variant v, int sweeps) {
  Sweep r{x0, std::vector<Real>(m.get<Distance>().size(), Real(0))};
  SolveContext sc = context(m, r.x, x_prev, v);
  const std::span<const Distance> cs(m.get<Distance>());
  for (int i = 0; i < sweeps; ++i) {
    if (v == Variant::damped)
      project_all<Distance, true>(cs, r.lambda, sc);
    else
      project_all<Distance, false>(cs, r.lambda, sc);
  }
  return r;
}

Real max_diff(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  Real d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, (a[i] - b[i]).cwiseAbs().maxCoeff());
  return d;
}

// A cloth with pins, mixed compliances and damping, its particles jittered
// (so every edge is violated) and given a velocity (x - x_prev), plus extra
// random edges between arbitrary particles, a degenerate pair (two
// coincident particles) and a pair of kinematic particles (zero
// denominator when rigid). Colours are then of uneven lengths.
struct Case {
  Model model;
  std::vector<Vec3> x, x_prev;
};

Case make_case(Variant v) {
  SceneDesc sd;
  ClothGridDesc d;
  d.nx = 9;
  d.ny = 7;
  d.pinned = {{0, 0}, {8, 0}};
  d.stretch = Material{Real(1e-6), v == Variant::damped ? Real(5) : Real(0), Real(0.9)};
  d.shear_mat = Material{Real(1e-4), v == Variant::damped ? Real(2) : Real(0), Real(0.7)};
  d.bend_mat = Material{0, 0, Real(0.5)};
  const ClothGrid g = add_cloth_grid(sd, d);
  const Index n = sd.num_particles();
  std::mt19937 rng(7);
  std::uniform_int_distribution<Index> pick(0, n - 1);
  for (int k = 0; k < 40; ++k) {
    const Index a = pick(rng), b = pick(rng);
    if (a != b) sd.distances.push_back(DistanceDesc{a, b, std::nullopt, Material{Real(1e-5), 0, 1}});
  }
  // Degenerate: particle `c` placed on the kinematic pinned particle and
  // joined to it only, with rest 0.02 m (it stays there: nothing moves it).
  const Index c = sd.add_particle(sd.positions[std::size_t(g.pinned[0])], Real(0.01));
  sd.distances.push_back(DistanceDesc{g.pinned[0], c, Real(0.02), Material{Real(1e-5), 0, 1}});
  // Both ends kinematic, rigid: denominator 0.
  sd.distances.push_back(DistanceDesc{g.pinned[0], g.pinned[1], std::nullopt, Material{}});
  Case cs{compile(sd), {}, {}};
  std::uniform_real_distribution<Real> jitter(Real(-0.01), Real(0.01));  // m
  cs.x = cs.model.x0;
  cs.x_prev = cs.model.x0;
  for (std::size_t i = 0; i < cs.x.size(); ++i) {
    if (cs.model.inv_mass[i] == Real(0) || Index(i) == c) continue;
    cs.x[i] += Vec3(jitter(rng), jitter(rng), jitter(rng));
    cs.x_prev[i] = cs.x[i] - Vec3(jitter(rng), jitter(rng), jitter(rng));
  }
  return cs;
}

// Both sides run the same pair-distance kernel, the same operations on the
// same elements in the same order; only where the multiplier is stored
// differs. So they agree to the last bit unless the compiler contracts
// operations differently in the two instantiations (FMA with -march=native);
// allow 16 ulp of the coordinates (|x| <= ~1 m) and of the largest
// multiplier for that. The corrections must be far above that, and the array
// order must differ from the coloured one by far more, or the comparison
// would prove nothing.
void check_equivalence(Variant v, bool alternate) {
  const Case c = make_case(v);
  const int sweeps = 4;
  const Sweep col = coloured(c.model, c.x, c.x_prev, v, sweeps, alternate);
  const Sweep ref = reference(c.model, c.x, c.x_prev, v, sweeps, alternate);
  const Sweep arr = array_order(c.model, c.x, c.x_prev, v, sweeps);
  ASSERT_TRUE(test::all_finite(col.x));
  Real scale = 0, lscale = 0;
  for (const Vec3& p : ref.x) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  for (Real l : ref.lambda) lscale = std::max(lscale, std::abs(l));
  const Real tol = 16 * kEps * scale;
  const Real ltol = 16 * kEps * lscale;
  const Real dx = max_diff(col.x, ref.x);
  Real dl = 0;
  for (std::size_t k = 0; k < col.lambda.size(); ++k)
    dl = std::max(dl, std::abs(col.lambda[k] - ref.lambda[k]));
  std::printf("variant %d alternate %d: |dx| %.3g m (tol %.3g), |dlambda| %.3g (tol %.3g), "
              "array order differs by %.3g m\n",
              int(v), int(alternate), double(dx), double(tol), double(dl), double(ltol),
              double(max_diff(arr.x, ref.x)));
  EXPECT_LE(dx, tol);
  EXPECT_LE(dl, ltol);
  EXPECT_GT(max_diff(c.x, ref.x), 100 * tol);     // the sweeps moved the particles
  EXPECT_GT(max_diff(arr.x, ref.x), 100 * tol);   // a different order gives a different result
  // The degenerate pair is skipped: its multiplier stays 0 (element index:
  // second to last).
  EXPECT_EQ(col.lambda[col.lambda.size() - 2], Real(0));
  EXPECT_EQ(col.lambda.back(), Real(0));  // zero denominator: skipped
}

TEST(ColouredSweep, EqualsArrayKernelInScheduleOrderXpbd) { check_equivalence(Variant::xpbd, false); }
TEST(ColouredSweep, EqualsArrayKernelInScheduleOrderDamped) {
  check_equivalence(Variant::damped, false);
}
TEST(ColouredSweep, EqualsArrayKernelInScheduleOrderPbd) { check_equivalence(Variant::pbd, false); }
// Reversed sweeps (alternate_sweeps) visit the colours last to first.
TEST(ColouredSweep, ReversedVisitsColoursLastToFirst) {
  check_equivalence(Variant::xpbd, true);
  check_equivalence(Variant::damped, true);
}

// step() with coloured = true runs exactly the coloured sweep on Distance:
// one substep, one iteration, no gravity, from a jittered state, equals one
// sweep of the compiled stream (project_stream, what step() runs in XPBD)
// after the prediction (x + h v with v = 0 here), bit for bit, and the
// coloured pair-distance kernel's sweep to round-off (the stream kernel
// sums |d|^2 in its own order; test_distance_stream.cpp).
TEST(ColouredSweep, StepUsesTheSchedule) {
  Case c = make_case(Variant::xpbd);
  State s = make_state(c.model);
  s.x = c.x;
  StepConfig cfg;
  cfg.substeps = 1;
  cfg.iterations = 1;
  cfg.dt = Real(1) / Real(600);  // the h of context()
  cfg.gravity = Vec3::Zero();
  cfg.coloured = true;
  step(c.model, s, cfg);
  // Inside step the Pins are projected after Distance; they hold kinematic
  // particles, which a pin leaves where they are, so they change nothing.
  State ref = make_state(c.model);
  ref.x = c.x;
  const std::vector<Vec3> x_prev = c.x;
  prepare_stream(c.model, ref, cfg.dt);
  project_stream(c.model, ref, context(c.model, ref.x, x_prev, Variant::xpbd), true);
  EXPECT_EQ(max_diff(s.x, ref.x), Real(0));
  const auto& order = c.model.distance_colours.order;
  for (std::size_t j = 0; j < order.size(); ++j)
    EXPECT_EQ(s.lambdas<Distance>()[std::size_t(order[j])], ref.stream_lambda[j]) << j;
  const Sweep col = coloured(c.model, c.x, c.x, Variant::xpbd, 1, false);
  EXPECT_LE(max_diff(s.x, col.x), 16 * kEps);
  const Real moved = max_diff(col.x, c.x);
  EXPECT_GT(moved, 1e3 * 16 * kEps);  // the sweep did move particles
}

// The same over two substeps with gravity and moving particles, damped and
// not: step() with coloured = true is, per substep, the prediction
// (x_prev = x, v += h g for a movable particle, x += h v), one sweep of the
// compiled stream (project_stream: it copies the particles into its records
// itself) and the velocity update v = (x - x_prev) / h, bit for bit. Inside
// step() the prediction writes the stream's records and runs the previous
// substep's velocity update in the same pass (step.cpp, predict); this
// composes the three stages one after the other instead.
TEST(ColouredSweep, StepIsPredictionSweepAndVelocityUpdate) {
  for (Variant variant : {Variant::xpbd, Variant::damped}) {
    Case c = make_case(variant);
    State s = make_state(c.model);
    s.x = c.x;
    std::mt19937 rng(11);
    std::uniform_real_distribution<Real> speed(Real(-0.5), Real(0.5));  // m/s
    for (std::size_t i = 0; i < s.v.size(); ++i)
      if (c.model.inv_mass[i] > Real(0)) s.v[i] = Vec3(speed(rng), speed(rng), speed(rng));
    State ref = s;
    StepConfig cfg;
    cfg.substeps = 2;
    cfg.iterations = 1;
    cfg.dt = Real(2) / Real(600);
    cfg.coloured = true;
    step(c.model, s, cfg);
    const Real h = cfg.dt / Real(cfg.substeps);
    for (int sub = 0; sub < cfg.substeps; ++sub) {
      ref.x_prev = ref.x;
      for (std::size_t i = 0; i < ref.x.size(); ++i) {
        if (c.model.inv_mass[i] > Real(0)) ref.v[i] += h * cfg.gravity;
        ref.x[i] = ref.x[i] + h * ref.v[i];
      }
      prepare_stream(c.model, ref, h);
      SolveContext sc = context(c.model, ref.x, ref.x_prev, variant);
      sc.h = h;
      project_stream(c.model, ref, sc, true);
      for (std::size_t i = 0; i < ref.x.size(); ++i) ref.v[i] = (ref.x[i] - ref.x_prev[i]) * (Real(1) / h);
    }
    EXPECT_EQ(max_diff(s.x, ref.x), Real(0)) << int(variant);
    EXPECT_EQ(max_diff(s.v, ref.v), Real(0)) << int(variant);
    EXPECT_GT(max_diff(s.x, c.x), Real(1e-4)) << "the particles did not move";
  }
}

TEST(ColouredSweep, RejectsAModelWithoutASchedule) {
  Case c = make_case(Variant::xpbd);
  Model m = c.model;
  m.distance_colours = ColourSchedule{};
  State s = make_state(m);
  StepConfig cfg;
  cfg.coloured = true;
  EXPECT_TRUE(test::config_error_names(m, s, cfg, {"StepConfig.coloured", "distance_colours"}));
  cfg.coloured = false;  // the array order does not need it
  EXPECT_NO_THROW(step(m, s, cfg));
}

// ---------------------------------------------------------------------------
// Physics with the coloured sweep.

// docs/design.md section 6: 20 particles of 1 kg (particle 0 pinned, kinematic),
// l = 0.01 m, g = 10 m/s^2, compliance 1e-6 m/N. Link k holds N-1-k
// particles, so at equilibrium it carries (N-1-k) m g and is stretched by
// alpha (N-1-k) m g (1.9e-4 m for link 0, 1e-5 m for the last).
// (The force from lambda is test_hanging_chain.cpp's subject; after 100
// iterations per substep, float's round-off in C accumulates in lambda
// beyond its 1e-3 there, so it is not repeated here.)
// Tolerance: 1e-3 of the stretch (as test_hanging_chain.cpp allows for the
// force) plus the round-off of a length computed from two coordinates near
// 1 m (a few ulp of 1 m: 8 eps). The stretch (unlike the force from lambda,
// see test_hanging_chain.cpp) is only right where each substep's solve
// converges: at 20 iterations per substep the worst link was 0.29% off
// with the two colours of a chain (even links, then odd links), and 0.14%
// in array order (measured); at 100 both are within 2e-11.
TEST(ColouredSweep, HangingChainSettlesToClosedFormStretch) {
  constexpr int N = 20;
  constexpr Real m = 1, g = 10, l = Real(0.01), alpha = Real(1e-6);
  SceneDesc sd;
  RopeDesc rope;
  rope.n = N;
  rope.start = Vec3(0, 1, 0);
  rope.dir = -Vec3::UnitY();
  rope.spacing = l;
  rope.mass = m;
  rope.pin_first = true;
  rope.mat = Material{alpha, 0, 1};
  add_rope(sd, rope);
  const Model model = compile(sd);
  ASSERT_EQ(model.distance_colours.num_colours(), 2);
  State s = make_state(model);
  StepConfig cfg;
  cfg.substeps = 10;
  cfg.iterations = 100;
  cfg.gravity = Vec3(0, -g, 0);
  cfg.drag = 5;  // 1/s: lets the start-up transient decay; no effect at rest
  cfg.coloured = true;
  for (int n = 0; n < 600; ++n) step(model, s, cfg);
  ASSERT_TRUE(test::all_finite(s.x));
  for (int k = 0; k < N - 1; ++k) {
    const Real stretch = (s.x[std::size_t(k)] - s.x[std::size_t(k) + 1]).norm() - l;
    const Real expected = alpha * Real(N - 1 - k) * m * g;
    EXPECT_NEAR(stretch, expected, 1e-3 * expected + 8 * kEps) << "link " << k;
  }
}

// Fig. 5-like: a 10 x 10 cloth (1 m, 1 kg, structural + shear edges of
// compliance 0.04 m/N, docs/fig5.md) pinned at two corners falls and swings
// for 2 s at 1 substep x 100 iterations. Converged XPBD does not depend on
// the solver's iteration details (Fig. 5's claim: its metrics spread < 1%
// across 5..100 iterations), and the Gauss-Seidel order is another such
// detail, so the coloured and the array-order cloth must agree to the same
// 1%: centre and lowest heights at every frame after 0.1 s, relative to the
// array order's value (each below 5 cm in magnitude only before 0.1 s).
TEST(ColouredSweep, HangingClothFollowsArrayOrder) {
  SceneDesc sd;
  ClothGridDesc d;
  d.nx = d.ny = 10;
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  d.origin = Vec3(Real(-0.5), 0, 0);
  d.pinned = {{0, 0}, {9, 0}};
  d.stretch.compliance = d.shear_mat.compliance = Real(0.04);
  d.bend_distance = false;
  const ClothGrid grid = add_cloth_grid(sd, d);
  const Model model = compile(sd);
  const std::size_t centre = std::size_t(grid.at(5, 5));
  StepConfig cfg;
  cfg.substeps = 1;
  cfg.iterations = 100;
  StepConfig col = cfg;
  col.coloured = true;
  State a = make_state(model), b = make_state(model);
  Real worst = 0, lowest = 0;
  for (int f = 1; f <= 120; ++f) {
    step(model, a, cfg);
    step(model, b, col);
    ASSERT_TRUE(test::all_finite(b.x));
    if (Real(f) * cfg.dt < Real(0.1)) continue;
    Real low_a = a.x[0].y(), low_b = b.x[0].y();
    for (std::size_t i = 0; i < a.x.size(); ++i) {
      low_a = std::min(low_a, a.x[i].y());
      low_b = std::min(low_b, b.x[i].y());
    }
    lowest = std::min(lowest, low_a);
    worst = std::max(worst, std::abs(b.x[centre].y() - a.x[centre].y()) / std::abs(a.x[centre].y()));
    worst = std::max(worst, std::abs(low_b - low_a) / std::abs(low_a));
  }
  std::printf("hanging cloth: largest relative height difference coloured vs array order %.3g\n",
              double(worst));
  EXPECT_LT(lowest, Real(-0.5));  // it really fell and swung
  EXPECT_LT(worst, Real(0.01));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
