// Where the library's messages go. The library never prints: what it has to say (which backend
// `backend: auto` took, why OpenCL was not usable) goes to the callback set here. Without one,
// messages are dropped. The `freespace` command installs a callback that prints to stderr.
#pragma once

#include <functional>
#include <string>

namespace freespace {

enum class LogLevel {
  kInfo,     // a choice the library made that the caller may want to know (backend taken)
  kWarning,  // something did not go as configured but the library carried on (a fallback)
};

// Receives one message, without a trailing newline, e.g. "backend auto: using tbb".
using LogCallback = std::function<void(LogLevel level, const std::string& message)>;

// Sets the process-wide callback (an empty function drops messages, the default) and returns
// the previous one. Thread-safe; the callback may be called from any thread that creates an
// Estimator, one call at a time.
LogCallback SetLogCallback(LogCallback callback);

const char* ToString(LogLevel level);  // "info", "warning"

}  // namespace freespace
