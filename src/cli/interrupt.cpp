#include "interrupt.hpp"

#include <csignal>

namespace freespace::cli {
namespace {

volatile std::sig_atomic_t g_caught = 0;
struct sigaction g_previous_int, g_previous_term;

extern "C" void OnSignal(int signal) { g_caught = signal; }

// A signal the process was started ignoring (nohup, a background job of a script) stays
// ignored.
void Catch(int signal, struct sigaction* previous) {
  sigaction(signal, nullptr, previous);
  if (previous->sa_handler == SIG_IGN) return;
  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  // A second signal ends the process: the first left the default action in place.
  action.sa_flags = SA_RESETHAND | SA_RESTART;
  sigaction(signal, &action, nullptr);
}

}  // namespace

InterruptGuard::InterruptGuard() {
  g_caught = 0;
  Catch(SIGINT, &g_previous_int);
  Catch(SIGTERM, &g_previous_term);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &g_previous_int, nullptr);
  sigaction(SIGTERM, &g_previous_term, nullptr);
}

int InterruptGuard::caught() const { return g_caught; }

const char* SignalName(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return "a signal";
}

}  // namespace freespace::cli
