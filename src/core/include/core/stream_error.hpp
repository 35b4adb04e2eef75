// The OutputError of a file stream that failed, with the system's reason.
#pragma once

#include <cerrno>
#include <cstring>
#include <string>

#include "freespace/errors.hpp"

namespace freespace {

// "PATH: WHAT: REASON", REASON the text of errno, which the failing system call sets on the
// platforms this builds on (clear errno before the stream's call); an ofstream does not promise
// it, hence the fallback.
inline OutputError StreamError(const std::string& path, const char* what) {
  const std::string reason = errno != 0 ? std::strerror(errno) : "the stream reported an error";
  return OutputError(path + ": " + what + ": " + reason);
}

}  // namespace freespace
