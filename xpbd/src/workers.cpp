#include "xpbd/workers.hpp"

#include <algorithm>
#include <string>

#include "xpbd/error.hpp"

namespace xpbd {
namespace {

constexpr int kSpins = 100000;     // polls before a thread blocks
constexpr int kYieldEvery = 1024;  // polls between two yields

// Polls until ready() (yielding now and then: with more threads than free
// cores, the thread being waited for may need this core), then blocks on
// `a` until ready().
template <class T, class Ready>
void wait_until(std::atomic<T>& a, Ready ready) {
  for (int spin = 0; spin < kSpins; ++spin) {
    if (ready()) return;
    if (spin % kYieldEvery == kYieldEvery - 1) std::this_thread::yield();
  }
  for (;;) {
    const T v = a.load(std::memory_order_seq_cst);
    if (ready()) return;
    a.wait(v, std::memory_order_seq_cst);
  }
}

}  // namespace

Workers::Workers(int threads) {
  if (threads < 1) throw ConfigError("Workers: threads must be >= 1, got " + std::to_string(threads));
  helpers_.reserve(static_cast<std::size_t>(threads - 1));
  for (int k = 1; k < threads; ++k) helpers_.emplace_back([this, k] { helper_loop(k); });
}

Workers::~Workers() {
  begin_setup();
  stop_ = true;
  publish();
  for (std::thread& t : helpers_) t.join();
}

void Workers::begin_setup() {
  generation_.fetch_add(1, std::memory_order_seq_cst);  // odd: no helper enters now
  wait_until(active_, [&] { return active_.load(std::memory_order_seq_cst) == 0; });
}

void Workers::publish() {
  generation_.fetch_add(1, std::memory_order_seq_cst);  // even: the job is out
  generation_.notify_all();
}

void Workers::run_task(int t) {
  try {
    (*job_)(t);
  } catch (...) {
    std::lock_guard lock(error_mutex_);
    if (!error_) error_ = std::current_exception();
  }
  if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == tasks_) done_.notify_one();
}

void Workers::work(int slot) {
  // Home tasks first (slot, slot + threads, ...): split() hands out pieces
  // in the same order every time, so a thread keeps working on the same
  // data from one job to the next and finds it in its own cache. Then any
  // task nobody has claimed yet (a late or descheduled thread's).
  const int stride = threads();
  for (int t = slot; t < tasks_; t += stride)
    if (claimed_[static_cast<std::size_t>(t)].exchange(1, std::memory_order_acq_rel) == 0) run_task(t);
  for (int t = 0; t < tasks_; ++t)
    if (claimed_[static_cast<std::size_t>(t)].load(std::memory_order_relaxed) == 0 &&
        claimed_[static_cast<std::size_t>(t)].exchange(1, std::memory_order_acq_rel) == 0)
      run_task(t);
}

void Workers::helper_loop(int slot) {
  std::uint64_t seen = 0;
  for (;;) {
    // A job is an even generation this helper has not entered yet.
    std::uint64_t g = 0;
    wait_until(generation_, [&] {
      g = generation_.load(std::memory_order_seq_cst);
      return g != seen && (g & 1) == 0;
    });
    // Enter, then check that the caller has not begun the next setup
    // meanwhile (it waits for active_ == 0 after making the generation odd).
    active_.fetch_add(1, std::memory_order_seq_cst);
    if (generation_.load(std::memory_order_seq_cst) != g) {
      if (active_.fetch_sub(1, std::memory_order_seq_cst) == 1) active_.notify_one();
      continue;
    }
    seen = g;
    const bool stop = stop_;
    if (!stop) {
      if (phase_job_ != nullptr)
        work_phases(slot);
      else
        work(slot);
    }
    if (active_.fetch_sub(1, std::memory_order_seq_cst) == 1) active_.notify_one();
    if (stop) return;
  }
}

void Workers::run(int tasks, const std::function<void(int)>& f) {
  if (tasks <= 0) return;
  if (helpers_.empty() || tasks == 1) {
    for (int t = 0; t < tasks; ++t) f(t);
    return;
  }
  begin_setup();
  job_ = &f;
  phase_job_ = nullptr;
  tasks_ = tasks;
  error_ = nullptr;
  if (claimed_size_ < static_cast<std::size_t>(tasks)) {
    claimed_ = std::make_unique<std::atomic<unsigned char>[]>(static_cast<std::size_t>(tasks));
    claimed_size_ = static_cast<std::size_t>(tasks);
  }
  for (int t = 0; t < tasks; ++t) claimed_[static_cast<std::size_t>(t)].store(0, std::memory_order_relaxed);
  done_.store(0, std::memory_order_relaxed);
  publish();
  work(0);
  // Done when every task has run, whoever ran it: a helper that has not
  // woken yet is not waited for (it finds no task left when it does).
  wait_until(done_, [&] { return done_.load(std::memory_order_acquire) == tasks; });
  if (error_) std::rethrow_exception(error_);
}

void Workers::run_phase_task(int p, int t) {
  try {
    (*phase_job_)(p, t);
  } catch (...) {
    std::lock_guard lock(error_mutex_);
    if (!error_) error_ = std::current_exception();
  }
  const int n = phase_tasks_[static_cast<std::size_t>(p)];
  std::atomic<int>& done = phase_done_[static_cast<std::size_t>(p)];
  if (done.fetch_add(1, std::memory_order_acq_rel) + 1 == n) done.notify_all();
}

void Workers::work_phases(int slot) {
  const std::vector<int>& tasks = phase_tasks_;
  const int stride = threads();
  for (std::size_t p = 0; p < tasks.size(); ++p) {
    const int n = tasks[p];
    std::atomic<unsigned char>* const claimed = claimed_.get() + phase_first_[p];
    // As work(): home tasks first, then any not yet claimed.
    for (int t = slot; t < n; t += stride)
      if (claimed[t].exchange(1, std::memory_order_acq_rel) == 0) run_phase_task(int(p), t);
    for (int t = 0; t < n; ++t)
      if (claimed[t].load(std::memory_order_relaxed) == 0 && claimed[t].exchange(1, std::memory_order_acq_rel) == 0)
        run_phase_task(int(p), t);
    // The phase's barrier: its writes are seen by every task of the next.
    std::atomic<int>& done = phase_done_[p];
    wait_until(done, [&] { return done.load(std::memory_order_acquire) == n; });
  }
}

void Workers::run_phases(const std::vector<int>& tasks, const std::function<void(int, int)>& f) {
  const std::size_t phases = tasks.size();
  bool one_each = true;
  for (const int n : tasks) one_each = one_each && n <= 1;
  if (helpers_.empty() || one_each) {
    for (std::size_t p = 0; p < phases; ++p)
      for (int t = 0; t < tasks[p]; ++t) f(int(p), t);
    return;
  }
  begin_setup();
  job_ = nullptr;
  phase_job_ = &f;
  phase_tasks_.resize(phases);
  for (std::size_t p = 0; p < phases; ++p) phase_tasks_[p] = std::max(tasks[p], 0);
  error_ = nullptr;
  phase_first_.resize(phases);
  std::size_t total = 0;
  for (std::size_t p = 0; p < phases; ++p) {
    phase_first_[p] = total;
    total += std::size_t(phase_tasks_[p]);
  }
  if (claimed_size_ < total) {
    claimed_ = std::make_unique<std::atomic<unsigned char>[]>(total);
    claimed_size_ = total;
  }
  for (std::size_t k = 0; k < total; ++k) claimed_[k].store(0, std::memory_order_relaxed);
  if (phase_done_size_ < phases) {
    phase_done_ = std::make_unique<std::atomic<int>[]>(phases);
    phase_done_size_ = phases;
  }
  for (std::size_t p = 0; p < phases; ++p) phase_done_[p].store(0, std::memory_order_relaxed);
  publish();
  work_phases(0);
  if (error_) std::rethrow_exception(error_);
}

}  // namespace xpbd
