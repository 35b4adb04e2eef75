// Threads of a backend's own for work that must stay on one thread per device: the OpenCL
// backend split over several CPU devices (BackendConfig::opencl_devices) runs part of every
// split kernel on each device, and PoCL's basic device runs a command on the thread that
// enqueues it, so each device needs a thread of its own to use a core of its own. The estimator
// runs the clutter filter's parallel passes on the same crew (Backend::HostCrew), so that no
// other pool of threads competes with it for the cores.
//
// Run(parts, task) hands the parts 0 .. parts - 1 out to the calling thread (thread 0) and the
// helpers (threads 1 .. helpers()), each part to whichever thread asks first, and returns once
// every part is done. A helper that is asleep when a round starts joins late or not at all; the
// calling thread then runs the parts itself, so a round never waits for a wake-up.
//
// Between rounds a helper polls for the next one while the crew is awake, yielding its core to
// any other thread that is ready, and otherwise sleeps. Wake() keeps it awake for `window` (each
// call anew), Rest() for `linger` more, so helpers never poll for long unless told again.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace freespace {

// One step of a spin-wait: tells the core that the thread is only polling.
inline void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

class Crew {
 public:
  explicit Crew(int helpers, std::chrono::microseconds linger = std::chrono::microseconds(0),
                std::chrono::microseconds window = std::chrono::microseconds(2000));
  ~Crew();
  Crew(const Crew&) = delete;
  Crew& operator=(const Crew&) = delete;

  static constexpr int kMaxParts = 65535;  // of one Run

  int helpers() const { return int(threads_.size()); }
  // Helpers asleep now (for the tests).
  int sleeping() const { return sleepers_.load(); }

  // Runs task(p, thread) once for every p in [0, parts), on the calling thread (thread 0) and on
  // the helpers (1 .. helpers()) that ask for work before the parts run out; returns when all
  // are done. Rethrows the first exception a part threw (the other parts still run). Not
  // reentrant; one caller. Allocates nothing. At most kMaxParts parts.
  template <typename Task>
  void Run(int parts, const Task& task) {
    RunErased(parts, &Invoke<Task>, &task);
  }

  // For `window` from now (until Rest() or the next Wake()), idle helpers poll for the next
  // round instead of sleeping (and wake now if they sleep), so that rounds close together find
  // them ready. Rest(): only for `linger` more.
  void Wake();
  void Rest();

 private:
  using Erased = void (*)(const void* task, int part, int thread);
  template <typename Task>
  static void Invoke(const void* task, int part, int thread) {
    (*static_cast<const Task*>(task))(part, thread);
  }
  void RunErased(int parts, Erased invoke, const void* task);
  void Stop();  // stops and joins the helpers
  void Loop(int thread);
  // Claims and runs parts of the current round until none is left.
  void Work(int thread);

  // The round (high 32 bits), its number of parts (16 bits) and its next unclaimed part (low 16
  // bits), in one word: a claim is checked against, and lands in, the round it read.
  std::atomic<std::uint64_t> state_{0};
  std::atomic<Erased> invoke_{nullptr};
  std::atomic<const void*> task_{nullptr};
  std::atomic<int> done_{0};
  const std::chrono::steady_clock::duration linger_, window_;
  std::atomic<std::int64_t> poll_until_{0};  // steady_clock ticks: idle helpers poll until then
  std::atomic<std::uint64_t> wakes_{0};      // Wake() calls, for the sleepers
  std::atomic<bool> stop_{false};
  std::atomic<int> sleepers_{0};

  std::mutex mutex_;  // guards the sleep and error_
  std::condition_variable wake_;
  std::exception_ptr error_;
  std::vector<std::thread> threads_;
};

}  // namespace freespace
