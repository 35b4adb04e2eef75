// The process-wide log callback (freespace/log.hpp). One mutex serialises setting the callback
// and calling it, so a callback never runs twice at once and is never swapped while running.
#include "core/log.hpp"

#include <mutex>
#include <utility>

namespace freespace {
namespace {

std::mutex& CallbackMutex() {
  static std::mutex mutex;
  return mutex;
}

LogCallback& Callback() {
  static LogCallback callback;
  return callback;
}

}  // namespace

LogCallback SetLogCallback(LogCallback callback) {
  std::lock_guard<std::mutex> lock(CallbackMutex());
  return std::exchange(Callback(), std::move(callback));
}

void Log(LogLevel level, const std::string& message) {
  std::lock_guard<std::mutex> lock(CallbackMutex());
  if (Callback()) Callback()(level, message);
}

const char* ToString(LogLevel level) {
  switch (level) {
    case LogLevel::kInfo:
      return "info";
    case LogLevel::kWarning:
      return "warning";
  }
  return "unknown";
}

}  // namespace freespace
