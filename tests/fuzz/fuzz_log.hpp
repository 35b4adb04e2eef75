// Shared by the log-reader fuzz targets: writes the input to a private temporary file and reads
// every scan through the reader of one format. The readers' contract (include/freespace/io.hpp,
// docs/behaviour.md): OpenLog may throw InputError for a file it cannot use; Next() never
// throws, every problem is a reported issue whose message is short and printable. Anything
// else escaping, or a broken message, aborts the run, which libFuzzer reports.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>

#include "freespace/errors.hpp"
#include "freespace/io.hpp"

namespace freespace::fuzz {

// Aborts unless `text` is at most `limit` bytes of printable ASCII.
inline void CheckMessage(const std::string& text, std::size_t limit) {
  if (text.size() > limit) std::abort();
  for (const char c : text) {
    if (c < 0x20 || c > 0x7e) std::abort();
  }
}

inline int ReadLog(const std::uint8_t* data, std::size_t size, LogFormat format,
                   const char* suffix) {
  static const std::string path = "/tmp/freespace-fuzz-" + std::to_string(getpid()) + suffix;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    if (!out) std::abort();  // the harness itself failed, not the reader
  }
  LogOptions options;
  options.format = format;
  std::unique_ptr<LogReader> reader;
  try {
    reader = OpenLog(path, options);
  } catch (const InputError& e) {
    CheckMessage(e.what(), path.size() + 400);
    return 0;  // documented: a file that is no usable log
  }
  Scan scan;
  for (int n = 0; n < 100000 && reader->Next(&scan); ++n) {
    for (const LogIssue& issue : reader->TakeIssues()) CheckMessage(issue.message, 400);
  }
  for (const LogIssue& issue : reader->TakeIssues()) CheckMessage(issue.message, 400);
  return 0;
}

}  // namespace freespace::fuzz
