// Ctrl-C (SIGINT) and SIGTERM as a request to stop: a long command finishes the scan at hand,
// closes what it writes and says it was interrupted, instead of dying with its files cut short.
#pragma once

namespace freespace::cli {

// While one lives, SIGINT and SIGTERM are caught and remembered (one the process was started
// ignoring stays ignored); a second signal of the same kind ends the process as it would have
// without the guard (the handler resets itself). The previous handlers come back when it is
// destroyed. One at a time.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  // The signal caught (SIGINT or SIGTERM), 0 while none has come.
  int caught() const;
};

// "SIGINT", "SIGTERM", or "a signal".
const char* SignalName(int signal);

// The shell's code for a process that a signal ended: 128 + signal.
inline int ExitCodeOf(int signal) { return 128 + signal; }

}  // namespace freespace::cli
