// Where the recorded data and the project's files are.
#include "support/paths.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace freespace::test {

std::string DataDir() {
  if (const char* env = std::getenv("FREESPACE_DATA_DIR")) {
    if (std::filesystem::is_directory(env)) return env;
  }
  if (std::filesystem::is_directory(FREESPACE_DEFAULT_DATA_DIR)) return FREESPACE_DEFAULT_DATA_DIR;
  return "";
}

std::string FullDataDir() {
  if (const char* env = std::getenv("FREESPACE_FULL_DATA_DIR")) {
    if (std::filesystem::is_directory(env)) return env;
  }
  const std::string beside = std::string(FREESPACE_SOURCE_DIR) + "/../shared/data";
  return std::filesystem::is_directory(beside) ? beside : "";
}

std::string SourcePath(const std::string& relative) {
  return std::string(FREESPACE_SOURCE_DIR) + "/" + relative;
}

std::string ReadSourceFile(const std::string& relative) {
  std::ifstream in(SourcePath(relative));
  if (!in) throw std::runtime_error("cannot read " + SourcePath(relative));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

Config LoadProjectConfig(const std::string& name) {
  const Config config = Config::FromYamlFile(SourcePath("configs/" + name));
  config.Validate();
  return config;
}

}  // namespace freespace::test
