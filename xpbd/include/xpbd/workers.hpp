#pragma once
// A small pool of persistent threads for the coloured sweep
// (StepConfig::workers; the Bullet bridge also runs its contact search on
// it, xpbd_bullet::SystemSettings::workers). The elements of one colour share no particle, so
// any split of a colour across threads projects exactly what one thread
// would: the result is bit for bit the single-threaded coloured sweep's,
// whatever the number of threads (tests/unit/test_workers.cpp).
//
// run(tasks, f) calls f(t) once for every t in [0, tasks), spread over the
// calling thread and the helpers, and returns when all calls have returned.
// Thread k (0: the calling thread) first takes its own tasks, k, k + T, ...
// for T threads, then any task no thread has taken yet. The sweeps split
// their work into pieces in the same order every time, so a thread works on
// the same particles from one colour and substep to the next and finds
// them in its own cache (when any free thread took the next task, a piece
// often moved between cores, and two threads gave the coloured step
// 0.94-1.03x at 64 x 64 and 1.32-1.37x at 128 x 128, where they now give
// 1.16-1.32x and 1.64-1.76x; docs/bench-threads.md, "Threads"). run() waits
// for the tasks, not for the helpers: when a helper is not running (more
// threads than free cores), the others take its tasks instead of waiting
// for it to be scheduled. Waiting threads poll (up to 100,000 polls,
// yielding every 1,024, so that the next colour and the next substep find
// them awake), then block (std::atomic::wait): a pool left idle stops using
// CPU. On the 2-core development machine a helper starts its task a median
// 0.45 us after the job is out, and a run of 2 empty tasks costs about
// 760-780 ns (140-260 ns when the calling thread used to take both).
// Threads pay from about 64 x 64 up; the sweeps split only pieces large
// enough (xpbd/src/stream.hpp), and at 32 x 32 two threads give
// 0.93-0.95x one thread (docs/bench-threads.md, "Where threads start to
// pay"). run_phases(tasks, f) runs several such jobs one after another
// (the colours of a sweep, then the records' copy back) with one wake-up
// of the helpers, the threads waiting for each other between phases: at
// 128 x 128, a run of two tasks cost about 2 us beyond its work (1.2 us of
// setup and wake-up, 0.8 us of imbalance) about 280 times per step, and
// two threads went from 1.54-1.60x one thread to 1.64-1.68x
// (docs/bench-threads.md, "One job per sweep"). One Workers serves one
// step() at a time; it is not itself
// thread-safe. An exception thrown by f is rethrown by run() (the first
// one), after every task has finished.
#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace xpbd {

class Workers {
 public:
  // threads >= 1: the calling thread plus threads - 1 helpers. Throws
  // ConfigError for threads < 1.
  explicit Workers(int threads);
  ~Workers();
  Workers(const Workers&) = delete;
  Workers& operator=(const Workers&) = delete;

  int threads() const { return static_cast<int>(helpers_.size()) + 1; }
  void run(int tasks, const std::function<void(int)>& f);
  // Phases one after another in one job: phase p has tasks[p] tasks (>= 0),
  // each called as f(p, t) and spread over the threads as run() spreads
  // its tasks; no task of phase p + 1 starts before every task of phase p
  // has returned. The same calls as run() phase by phase, with one wake-up
  // of the helpers instead of one per phase (the colours of a sweep).
  void run_phases(const std::vector<int>& tasks, const std::function<void(int, int)>& f);

 private:
  void helper_loop(int slot);
  // Runs the current job's tasks of thread `slot` (0: the calling thread),
  // then any task not yet claimed.
  void work(int slot);
  void run_task(int t);
  // The phases of the current run_phases job, as work() for run().
  void work_phases(int slot);
  void run_phase_task(int p, int t);
  void begin_setup();  // no helper inside the job fields after this
  void publish();      // the job fields are out

  std::vector<std::thread> helpers_;
  // Even: a job is out (or none yet); odd: the calling thread is setting
  // one up, and no helper may read the fields below.
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<int> active_{0};  // helpers inside the current job
  std::atomic<int> done_{0};    // tasks of the current job that have returned
  // Per task of the current job: 1 once a thread has taken it.
  std::unique_ptr<std::atomic<unsigned char>[]> claimed_;
  std::size_t claimed_size_ = 0;
  int tasks_ = 0;
  const std::function<void(int)>* job_ = nullptr;
  // A run_phases job (job_ is null then): the tasks per phase, where each
  // phase's claim flags start in claimed_, and the tasks of each phase
  // that have returned.
  const std::function<void(int, int)>* phase_job_ = nullptr;
  std::vector<int> phase_tasks_;  // a copy: a late helper reads it after run_phases returned
  std::vector<std::size_t> phase_first_;
  std::unique_ptr<std::atomic<int>[]> phase_done_;
  std::size_t phase_done_size_ = 0;
  bool stop_ = false;
  std::mutex error_mutex_;
  std::exception_ptr error_;
};

}  // namespace xpbd
