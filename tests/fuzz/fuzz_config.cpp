// libFuzzer target: Config::FromYaml and Validate on arbitrary text. The contract
// (include/freespace/config.hpp): any problem is a ConfigError naming the file, with a short
// printable message; no other exception escapes (a YAML exception would abort here).
#include <cstdint>
#include <cstdlib>
#include <string>

#include "freespace/config.hpp"
#include "freespace/errors.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    freespace::Config config = freespace::Config::FromYaml(text, "fuzz.yaml");
    config.Validate();
    // What a valid config writes reads back to the same config (for ASCII input; YAML is
    // UTF-8, and other bytes need not survive).
    bool ascii = true;
    for (const char c : text) ascii &= (static_cast<unsigned char>(c) < 0x80);
    const std::string yaml = config.ToYaml();
    if (ascii && freespace::Config::FromYaml(yaml, "again.yaml").ToYaml() != yaml) std::abort();
  } catch (const freespace::ConfigError& e) {
    const std::string message = e.what();
    if (message.rfind("fuzz.yaml", 0) != 0 && message.rfind("config: ", 0) != 0) std::abort();
    if (message.size() > 600) std::abort();
    for (const char c : message) {
      if (c < 0x20 || c > 0x7e) std::abort();
    }
  }
  return 0;
}
