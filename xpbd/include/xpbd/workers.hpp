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
// Tasks are taken one at a time by whichever thread is free, and run()
// waits for the tasks, not for the helpers: when the helpers are not
// running (more threads than free cores), the calling thread does the
// tasks itself instead of waiting for them to be scheduled. Waiting threads
// poll (up to 100,000 polls, yielding every 1,024, so that the next colour
// and the next substep find them awake), then block (std::atomic::wait): a
// pool left idle stops using CPU. A run of 2 empty tasks costs about
// 140-260 ns; two threads make the coloured step 1.26-2.11 times as fast
// from a 64 x 64 cloth up (docs/benchmarks.md, "Threads" and
// "bench_scale"). One Workers serves one step() at a time; it is not itself
// thread-safe. An exception thrown by f is rethrown by run() (the first
// one), after every task has finished.
#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
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

 private:
  void helper_loop();
  void work();         // takes tasks of the current job until none is left
  void begin_setup();  // no helper inside the job fields after this
  void publish();      // the job fields are out

  std::vector<std::thread> helpers_;
  // Even: a job is out (or none yet); odd: the calling thread is setting
  // one up, and no helper may read the fields below.
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<int> active_{0};  // helpers inside the current job
  std::atomic<int> next_{0};    // next task index of the current job
  std::atomic<int> done_{0};    // tasks of the current job that have returned
  int tasks_ = 0;
  const std::function<void(int)>* job_ = nullptr;
  bool stop_ = false;
  std::mutex error_mutex_;
  std::exception_ptr error_;
};

}  // namespace xpbd
