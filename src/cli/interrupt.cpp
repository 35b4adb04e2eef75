#include "interrupt.hpp"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>

namespace freespace::cli {
namespace {

// Written by the handler, which may run on any thread.
std::atomic<int> g_caught{0};
static_assert(std::atomic<int>::is_always_lock_free, "the handler needs a lock-free atomic");

constexpr int kSignals[] = {SIGINT, SIGTERM};
struct sigaction g_previous[2];
volatile std::sig_atomic_t g_installed[2] = {0, 0};  // the guard caught this one

extern "C" void OnSignal(int signal) {
  g_caught.store(signal);
  // Both back to their default action (sigaction is async-signal-safe): a second signal of
  // either kind ends the process.
  struct sigaction plain {};
  plain.sa_handler = SIG_DFL;
  sigemptyset(&plain.sa_mask);
  for (int k = 0; k < 2; ++k) {
    if (g_installed[k]) sigaction(kSignals[k], &plain, nullptr);
  }
}

}  // namespace

InterruptGuard::InterruptGuard() {
  g_caught.store(0);
  for (int k = 0; k < 2; ++k) {
    g_installed[k] = 0;
    sigaction(kSignals[k], nullptr, &g_previous[k]);
    // A signal the process was started ignoring (nohup, a background job of a script) stays
    // ignored.
    if (g_previous[k].sa_handler == SIG_IGN) continue;
    struct sigaction action {};
    action.sa_handler = OnSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    g_installed[k] = 1;
    sigaction(kSignals[k], &action, nullptr);
  }
}

InterruptGuard::~InterruptGuard() {
  for (int k = 0; k < 2; ++k) {
    if (g_installed[k]) sigaction(kSignals[k], &g_previous[k], nullptr);
    g_installed[k] = 0;
  }
}

int InterruptGuard::caught() const { return g_caught.load(); }

int InterruptGuard::Finish(int stopped_by) const {
  const int signal = stopped_by != 0 ? stopped_by : caught();
  if (signal == 0) return 0;
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  std::signal(signal, SIG_DFL);
  std::raise(signal);
  return 128 + signal;
}

const char* SignalName(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return "a signal";
}

}  // namespace freespace::cli
