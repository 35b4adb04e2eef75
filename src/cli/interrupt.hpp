// Ctrl-C (SIGINT) and SIGTERM as a request to stop: a long command finishes the scan at hand,
// closes what it writes and says it was interrupted, then ends by the signal, instead of dying
// with its files cut short.
#pragma once

namespace freespace::cli {

// While one lives, SIGINT and SIGTERM are caught and remembered (one the process was started
// ignoring stays ignored); after the first, both have their default action again, so that a
// second signal ends the process at once. The previous handlers come back when it is
// destroyed. One at a time.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  // The signal caught (SIGINT or SIGTERM), 0 while none has come.
  int caught() const;

  // The end of a command whose outputs are written, stopped by `stopped_by` (0: it went to its
  // end): ends the process by that signal, or by one caught since, with its default action
  // (after flushing the standard streams), as if it had not been caught, so that a calling
  // shell sees the signal (exit status 128 + signal) and stops a script as for any other
  // command. Returns 0 when no signal came (128 + signal should the process survive it).
  int Finish(int stopped_by = 0) const;
};

// "SIGINT", "SIGTERM", or "a signal".
const char* SignalName(int signal);

}  // namespace freespace::cli
