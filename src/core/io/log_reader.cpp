// LogReader basics and OpenLog(): format detection from the file's content.
#include <filesystem>
#include <fstream>
#include <string>

#include "freespace/config.hpp"
#include "freespace/errors.hpp"
#include "freespace/io.hpp"
#include "readers.hpp"
#include "text.hpp"

namespace freespace {

std::string LogIssue::ToString() const {
  return line > 0 ? file + ":" + std::to_string(line) + ": " + message : file + ": " + message;
}

std::vector<LogIssue> LogReader::TakeIssues() {
  std::vector<LogIssue> out;
  out.swap(issues_);
  return out;
}

void LogReader::Report(std::size_t line, std::string message) {
  issues_.push_back({path_, line, std::move(message)});
}

void LogReader::Note(std::size_t line, std::string message) {
  issues_.push_back({path_, line, std::move(message), true});
}

const char* ToString(LogFormat format) {
  switch (format) {
    case LogFormat::kAuto:
      return "auto";
    case LogFormat::kCarmen:
      return "carmen";
    case LogFormat::kKitti:
      return "kitti";
    case LogFormat::kNative:
      return "freespace";
  }
  return "?";
}

bool CycleReader::Next(std::vector<Scan>* cycle) {
  cycle->clear();
  lines_.clear();
  if (has_pending_) {
    cycle->push_back(std::move(pending_));
    line_ = last_line_ = pending_line_;
    lines_.push_back(pending_line_);
    has_pending_ = false;
  }
  while (int(cycle->size()) < sensors_) {
    Scan scan;
    if (!reader_.Next(&scan)) break;
    bool repeated = false;
    for (const Scan& s : *cycle) repeated = repeated || s.sensor == scan.sensor;
    if (repeated) {
      pending_ = std::move(scan);
      pending_line_ = reader_.line();
      has_pending_ = true;
      break;
    }
    if (cycle->empty()) line_ = reader_.line();
    last_line_ = reader_.line();
    lines_.push_back(last_line_);
    cycle->push_back(std::move(scan));
  }
  return !cycle->empty();
}

namespace {

LogFormat Detect(const std::string& path) {
  if (std::filesystem::is_directory(path)) return LogFormat::kKitti;  // a sequence folder
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  if (path.size() >= 4 && path.compare(path.size() - 4, 4, ".bin") == 0) return LogFormat::kKitti;
  std::string line;
  std::vector<std::string_view> fields;
  for (int n = 0; n < 1000 && std::getline(in, line); ++n) {
    if (io::IsCommentOrBlank(line)) continue;
    io::SplitFields(line, &fields);
    if (fields[0] == "FREESPACE_LOG") return LogFormat::kNative;
    for (const char* carmen : {"FLASER", "ROBOTLASER1", "ODOM", "PARAM", "SYNC", "RLASER",
                               "TRUEPOS", "NEFF", "RAWLASER1", "RAWLASER2", "ROBOTLASER2"}) {
      if (fields[0] == carmen) return LogFormat::kCarmen;
    }
    throw InputError(path + ": not a recognised log (first message '" + io::Excerpt(fields[0]) +
                     "'; expected a CARMEN log, a KITTI .bin frame or sequence folder, or a "
                     "FREESPACE_LOG file)");
  }
  throw InputError(path + ": empty log");
}

}  // namespace

void RequireLogPath(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error) throw InputError(path + ": cannot open: " + error.message());
  if (fs::is_regular_file(status) || fs::is_directory(status)) return;
  throw InputError(path + ": a pipe or a device, not a file; a log is read more than once, " +
                   "so write it to a file first");
}

std::unique_ptr<LogReader> OpenLog(const std::string& path, const LogOptions& options) {
  RequireLogPath(path);
  const LogFormat format = options.format == LogFormat::kAuto ? Detect(path) : options.format;
  switch (format) {
    case LogFormat::kCarmen:
      if (std::filesystem::is_directory(path)) throw InputError(path + ": a directory");
      return io::OpenCarmen(path, options);
    case LogFormat::kKitti:
      if (std::filesystem::is_directory(path)) return io::OpenKittiSequence(path, options);
      return io::OpenKitti(path, options);
    case LogFormat::kNative:
      if (std::filesystem::is_directory(path)) throw InputError(path + ": a directory");
      return io::OpenNative(path, options);
    case LogFormat::kAuto:
      break;
  }
  throw InputError(path + ": unknown log format");
}

std::string io::SensorProblem(const SensorConfig& sensor) {
  try {
    ValidateSensor(sensor);
  } catch (const ConfigError& e) {
    const std::string why = e.what();
    return why.rfind("config: ", 0) == 0 ? why.substr(8) : why;
  }
  return "";
}

}  // namespace freespace
