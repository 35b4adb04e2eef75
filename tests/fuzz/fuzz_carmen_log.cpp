// libFuzzer target: the carmen log reader on arbitrary bytes (see fuzz_log.hpp).
#include "fuzz_log.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return freespace::fuzz::ReadLog(data, size, freespace::LogFormat::kCarmen, ".log");
}
