// The library's side of freespace/log.hpp: how a layer hands a message to the caller's callback.
#pragma once

#include <string>

#include "freespace/log.hpp"

namespace freespace {

// Passes `message` to the callback set with SetLogCallback(); does nothing without one.
void Log(LogLevel level, const std::string& message);

}  // namespace freespace
