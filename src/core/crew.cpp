#include "core/crew.hpp"

#include <stdexcept>

namespace freespace {
namespace {

constexpr std::uint64_t kPartMask = 0xffffu;

int PartsOf(std::uint64_t state) { return int((state >> 16) & kPartMask); }
int NextOf(std::uint64_t state) { return int(state & kPartMask); }

std::int64_t Ticks(std::chrono::steady_clock::time_point t) { return t.time_since_epoch().count(); }

}  // namespace

Crew::Crew(int helpers, std::chrono::microseconds linger, std::chrono::microseconds window)
    : linger_(linger), window_(window) {
  threads_.reserve(std::size_t(helpers > 0 ? helpers : 0));
  try {
    for (int t = 1; t <= helpers; ++t) threads_.emplace_back([this, t] { Loop(t); });
  } catch (...) {
    Stop();  // the threads already started
    throw;
  }
}

Crew::~Crew() { Stop(); }

void Crew::Stop() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_.store(true);
  }
  wake_.notify_all();
  for (std::thread& thread : threads_) {
    if (thread.joinable()) thread.join();
  }
}

void Crew::RunErased(int parts, Erased invoke, const void* task) {
  if (parts <= 0) return;
  if (std::uint64_t(parts) > kPartMask) throw std::invalid_argument("Crew::Run: too many parts");
  error_ = nullptr;
  invoke_.store(invoke, std::memory_order_relaxed);
  task_.store(task, std::memory_order_relaxed);
  done_.store(0, std::memory_order_relaxed);
  const std::uint64_t round = (state_.load(std::memory_order_relaxed) >> 32) + 1;
  // Sequentially consistent, as are the sleeper count and the helpers' checks before they
  // sleep: either this sees the helper counted as a sleeper, or the helper sees the new round.
  state_.store(round << 32 | std::uint64_t(parts) << 16);  // also publishes the stores above
  if (sleepers_.load() > 0) {
    { const std::lock_guard<std::mutex> lock(mutex_); }  // a helper between check and wait
    wake_.notify_all();
  }
  Work(0);
  // The parts still running are on helpers; give their cores back if they were preempted.
  for (unsigned i = 1; done_.load(std::memory_order_acquire) < parts; ++i) {
    CpuRelax();
    if (i % 64 == 0) std::this_thread::yield();
  }
  if (error_) std::rethrow_exception(error_);
}

void Crew::Work(int thread) {
  std::uint64_t s = state_.load(std::memory_order_acquire);
  for (;;) {
    if (NextOf(s) >= PartsOf(s)) return;
    if (!state_.compare_exchange_weak(s, s + 1, std::memory_order_acq_rel,
                                      std::memory_order_acquire)) {
      continue;  // s now holds the current state, perhaps of a newer round
    }
    // task_ is the claimed round's: the next round's is stored only after every part of this
    // one is done, and this part is not.
    const int part = NextOf(s);
    try {
      invoke_.load(std::memory_order_relaxed)(task_.load(std::memory_order_relaxed), part, thread);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
    done_.fetch_add(1, std::memory_order_acq_rel);
    s = state_.load(std::memory_order_acquire);
  }
}

void Crew::Wake() {
  poll_until_.store(Ticks(std::chrono::steady_clock::now() + window_), std::memory_order_relaxed);
  // Sequentially consistent, as in Run: a helper about to sleep sees the new count, or this
  // sees it counted as a sleeper.
  wakes_.fetch_add(1);
  if (sleepers_.load() > 0) {
    { const std::lock_guard<std::mutex> lock(mutex_); }
    wake_.notify_all();
  }
}

void Crew::Rest() {
  poll_until_.store(Ticks(std::chrono::steady_clock::now() + linger_), std::memory_order_relaxed);
}

void Crew::Loop(int thread) {
  std::uint64_t seen = 0;        // the last round this thread looked at
  std::uint64_t seen_wakes = 0;  // and the Wake() calls it knew of
  while (!stop_.load(std::memory_order_acquire)) {
    const std::uint64_t round = state_.load(std::memory_order_acquire) >> 32;
    if (round != seen) {
      seen = round;
      Work(thread);
      continue;
    }
    seen_wakes = wakes_.load();
    if (Ticks(std::chrono::steady_clock::now()) < poll_until_.load(std::memory_order_relaxed)) {
      // Polling; give the core away to any thread that is ready to run.
      for (int i = 0; i < 64; ++i) CpuRelax();
      std::this_thread::yield();
      continue;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    sleepers_.fetch_add(1);
    wake_.wait(lock, [&] {
      return stop_.load() || wakes_.load() != seen_wakes || (state_.load() >> 32) != seen;
    });
    sleepers_.fetch_sub(1);
  }
}

}  // namespace freespace
