// Workers (workers.hpp) and the threaded coloured XPBD sweep
// (StepConfig::workers): every task runs once; the threaded step is the
// single-threaded coloured step bit for bit (with the AVX2 kernel where the
// CPU has it, and with the scalar kernel).
#include <gtest/gtest.h>

#include <algorithm>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/xpbd_test.hpp"
#include "xpbd/workers.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

TEST(Workers, EveryTaskRunsExactlyOnce) {
  for (int threads : {1, 2, 4}) {
    Workers w(threads);
    EXPECT_EQ(w.threads(), threads);
    for (int tasks : {0, 1, 7, 1000}) {
      std::vector<std::atomic<int>> hits(static_cast<std::size_t>(tasks));
      for (int round = 0; round < 3; ++round)
        w.run(tasks, [&](int t) { hits[static_cast<std::size_t>(t)].fetch_add(1); });
      for (int t = 0; t < tasks; ++t) EXPECT_EQ(hits[static_cast<std::size_t>(t)].load(), 3) << threads << " threads, task " << t;
    }
  }
}

// Many short jobs back to back, as the colours of a sweep are: each one's
// tasks all run once, with helpers entering late or not at all.
TEST(Workers, ManyShortJobsInARow) {
  for (int threads : {2, 3}) {
    Workers w(threads);
    int bad = 0;
    for (int round = 0; round < 20000; ++round) {
      const int tasks = 1 + round % 5;
      std::atomic<int> sum{0};
      w.run(tasks, [&](int t) { sum.fetch_add(t + 1); });
      bad += sum.load() != tasks * (tasks + 1) / 2;
    }
    EXPECT_EQ(bad, 0) << threads << " threads";
  }
}

// A thread busy with one of its own tasks does not hold up its others:
// with 2 threads and 4 tasks (the calling thread's own 0 and 2, the
// helper's 1 and 3), task 1 waits until task 3 has run. Whoever runs task
// 1, the other thread must take task 3, even where it is not its own.
// (Without taking others' tasks the wait times out after 5 s.)
TEST(Workers, ABusyThreadsOtherTasksAreTakenByTheOthers) {
  Workers w(2);
  for (int round = 0; round < 200; ++round) {
    std::atomic<bool> three_ran{false}, timed_out{false};
    std::atomic<int> ran{0};
    w.run(4, [&](int t) {
      if (t == 1) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
        while (!three_ran.load() && !timed_out.load())
          if (std::chrono::steady_clock::now() > until) timed_out = true;
      }
      if (t == 3) three_ran = true;
      ++ran;
    });
    ASSERT_FALSE(timed_out.load()) << "round " << round << ": task 3 waited for the thread busy with task 1";
    ASSERT_EQ(ran.load(), 4);
  }
}

TEST(Workers, ExceptionIsRethrownAndThePoolStillWorks) {
  Workers w(2);
  std::atomic<int> ran{0};
  EXPECT_THROW(w.run(8,
                     [&](int t) {
                       ++ran;
                       if (t == 5) throw std::runtime_error("task 5");
                     }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 8);  // the others still ran
  ran = 0;
  w.run(8, [&](int) { ++ran; });
  EXPECT_EQ(ran.load(), 8);
}

// run_phases: every task of every phase once, and no task of a phase
// before every task of the phase before has returned (each task of phase
// p reads how many of phase p - 1 have finished, after a short spin that
// gives another thread time to start the next phase early). Phases of 0
// and 1 tasks in between, and a throwing task: on a pool rethrown once
// every task has run, and the pool works on.
TEST(Workers, PhasesRunInOrderEachTaskOnce) {
  for (int threads : {1, 2, 4}) {
    Workers w(threads);
    const std::vector<int> tasks = {3, 0, 1, 5, 2, 7, 1, 4};
    std::vector<std::atomic<int>> finished(tasks.size());
    std::vector<std::atomic<int>> hits(tasks.size() * 8);
    std::atomic<int> early{0};
    for (int round = 0; round < 20; ++round) {
      for (auto& f : finished) f.store(0);
      w.run_phases(tasks, [&](int p, int t) {
        hits[std::size_t(p) * 8 + std::size_t(t)].fetch_add(1);
        int before = p > 0 ? finished[std::size_t(p - 1)].load() : 0;
        // The phase before the last non-empty one: 0 tasks counts as done.
        int q = p - 1;
        while (q > 0 && tasks[std::size_t(q)] == 0) --q;
        if (q >= 0 && q != p - 1) before = finished[std::size_t(q)].load();
        if (q >= 0 && before != tasks[std::size_t(q)]) early.fetch_add(1);
        const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(20);
        while (std::chrono::steady_clock::now() < until) {
        }
        finished[std::size_t(p)].fetch_add(1);
      });
    }
    EXPECT_EQ(early.load(), 0) << threads << " threads";
    for (std::size_t p = 0; p < tasks.size(); ++p)
      for (int t = 0; t < 8; ++t)
        EXPECT_EQ(hits[p * 8 + std::size_t(t)].load(), t < tasks[p] ? 20 : 0) << threads << " threads, phase " << p;
    std::atomic<int> ran{0};
    EXPECT_THROW(w.run_phases(tasks,
                              [&](int p, int t) {
                                ran.fetch_add(1);
                                if (p == 3 && t == 1) throw std::runtime_error("task");
                              }),
                 std::runtime_error);
    // On one thread the phases run in a plain loop, which stops at the
    // throw (6 tasks ran), as run() does.
    EXPECT_EQ(ran.load(), threads == 1 ? 6 : 23);
    std::atomic<int> after{0};
    w.run_phases({2, 2}, [&](int, int) { after.fetch_add(1); });
    EXPECT_EQ(after.load(), 4);
  }
}

TEST(Workers, BadThreadCountAndMissingColoursAreNamed) {
  try {
    Workers w(0);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("threads must be >= 1, got 0"), std::string::npos) << e.what();
  }
  SceneDesc d;
  add_cloth_grid(d, ClothGridDesc{});
  const Model m = compile(d);
  State s = make_state(m);
  Workers w(2);
  StepConfig cfg;
  cfg.workers = &w;  // coloured is off
  EXPECT_TRUE(test::config_error_names(m, s, cfg, {"StepConfig.workers", "coloured"}));
}

// A 64 x 64 cloth pinned at two corners, falling and swinging for 30
// steps: coloured XPBD (damped, alternating sweep directions), with and
// without threads. Positions, velocities and multipliers equal bit for
// bit. (Its colours hold about 2,000 distance elements each, so they are
// split: from 2 x 768 on, stream.hpp; PBD's coloured sweep is not
// threaded.) With `bending`, with dihedral bending too.
void check_bitwise(Method method, int threads, bool simd, bool bending) {
  SceneDesc d;
  ClothGridDesc g;
  g.nx = g.ny = 64;
  g.pins = ClothPins::top_corners;
  g.u = Vec3::UnitX();
  g.v = Vec3::UnitZ();  // horizontal: it falls and swings about the pinned edge
  g.stretch.damping = method == Method::xpbd ? Real(2) : Real(0);
  // Dihedral bending too (its XPBD stream is split over the threads as
  // well): on 64 x 64 its 14 colours hold 840 hinges on average, so most
  // are split.
  if (bending) {
    g.set_bending(ClothBending::dihedral, Material{Real(1e-4), Real(0.5), 1});
  }
  add_cloth_grid(d, g);
  const Model m = compile(d);
  Index largest = 0;  // distance elements in the largest colour
  for (Index c = 0; c < m.distance_colours.num_colours(); ++c)
    largest = std::max(largest, m.distance_colours.begin[std::size_t(c) + 1] - m.distance_colours.begin[std::size_t(c)]);
  ASSERT_GE(largest, 2 * 768) << "no colour is large enough to be split (stream.hpp, kMinDistancePerTask)";
  State one = make_state(m), many = make_state(m);
  StepConfig cfg;
  cfg.method = method;
  cfg.coloured = true;
  cfg.alternate_sweeps = true;
  cfg.iterations = 2;
  cfg.simd = simd;
  Workers w(threads);
  StepConfig threaded = cfg;
  threaded.workers = &w;
  for (int k = 0; k < 30; ++k) {
    step(m, one, cfg);
    step(m, many, threaded);
  }
  ASSERT_EQ(one.x.size(), many.x.size());
  Real moved = 0;
  for (std::size_t i = 0; i < one.x.size(); ++i) {
    EXPECT_EQ(one.x[i], many.x[i]) << "particle " << i;
    EXPECT_EQ(one.v[i], many.v[i]) << "particle " << i;
    moved = std::max(moved, (one.x[i] - m.x0[i]).norm());
  }
  EXPECT_EQ(one.lambdas<Distance>(), many.lambdas<Distance>());
  EXPECT_EQ(one.lambdas<DihedralBending>(), many.lambdas<DihedralBending>());
  EXPECT_GT(moved, Real(0.1));  // the cloth did fall and swing
}

TEST(Workers, ThreadedColouredStepIsBitwiseTheSingleThreadedOne) {
  check_bitwise(Method::xpbd, 2, true, false);
  check_bitwise(Method::xpbd, 3, true, false);
  check_bitwise(Method::xpbd, 2, false, false);
  check_bitwise(Method::xpbd, 2, true, true);
  check_bitwise(Method::xpbd, 4, true, true);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd
