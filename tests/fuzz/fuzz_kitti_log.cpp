// libFuzzer target: the kitti log reader on arbitrary bytes (see fuzz_log.hpp).
#include "fuzz_log.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return freespace::fuzz::ReadLog(data, size, freespace::LogFormat::kKitti, ".bin");
}
