#include "xpbd/workers.hpp"

#include <string>

#include "xpbd/error.hpp"

namespace xpbd {

Workers::Workers(int threads) {
  if (threads < 1) throw ConfigError("Workers: threads must be >= 1, got " + std::to_string(threads));
  helpers_.reserve(static_cast<std::size_t>(threads - 1));
  for (int k = 1; k < threads; ++k) helpers_.emplace_back([this] { helper_loop(); });
}

Workers::~Workers() {
  stop_ = true;
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  for (std::thread& t : helpers_) t.join();
}

void Workers::work() {
  for (;;) {
    const int t = next_.fetch_add(1, std::memory_order_relaxed);
    if (t >= tasks_) return;
    try {
      (*job_)(t);
    } catch (...) {
      std::lock_guard lock(error_mutex_);
      if (!error_) error_ = std::current_exception();
    }
  }
}

void Workers::helper_loop() {
  std::uint64_t seen = 0;
  for (;;) {
    // Spin a little (the next colour usually follows within microseconds),
    // then block until the generation changes.
    std::uint64_t g = generation_.load(std::memory_order_acquire);
    for (int spin = 0; g == seen && spin < 100000; ++spin) g = generation_.load(std::memory_order_acquire);
    if (g == seen) {
      generation_.wait(seen, std::memory_order_acquire);
      g = generation_.load(std::memory_order_acquire);
    }
    seen = g;
    if (stop_) return;
    work();
    busy_.fetch_sub(1, std::memory_order_acq_rel);
  }
}

void Workers::run(int tasks, const std::function<void(int)>& f) {
  if (tasks <= 0) return;
  if (helpers_.empty() || tasks == 1) {
    for (int t = 0; t < tasks; ++t) f(t);
    return;
  }
  job_ = &f;
  tasks_ = tasks;
  error_ = nullptr;
  next_.store(0, std::memory_order_relaxed);
  busy_.store(static_cast<int>(helpers_.size()), std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  work();
  while (busy_.load(std::memory_order_acquire) != 0) {
  }
  job_ = nullptr;
  if (error_) std::rethrow_exception(error_);
}

}  // namespace xpbd
