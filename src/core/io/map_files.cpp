// OccupancyGrid values and map files (freespace/map_io.hpp): map_server's PGM + YAML, written
// the way ROS's map_saver writes them (trinary image, first row northern, origin the lower-left
// corner), and the raw log-odds as a NumPy .npy (format 1.0).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/backend.hpp"
#include "core/stream_error.hpp"
#include "freespace/errors.hpp"
#include "freespace/map_io.hpp"
#include "io/text.hpp"

namespace freespace {
namespace {

void CheckView(const MapView& map, const char* where) {
  if (map.width <= 0 || map.height <= 0 || map.log_odds == nullptr) {
    throw std::invalid_argument(std::string(where) + ": empty map view (" +
                                std::to_string(map.width) + " x " + std::to_string(map.height) +
                                (map.log_odds == nullptr ? ", no log-odds" : "") + ")");
  }
}

// The shortest decimal that reads back as `v` (YAML readers parse it to the same double).
std::string Decimal(double v) {
  char text[40];
  for (int precision = 6; precision <= 17; ++precision) {
    std::snprintf(text, sizeof text, "%.*g", precision, v);
    if (std::strtod(text, nullptr) == v) break;
  }
  return text;
}

std::ofstream OpenOut(const std::string& path) {
  errno = 0;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw StreamError(path, "cannot create");
  return out;
}

void Finish(std::ofstream& out, const std::string& path) {
  errno = 0;
  out.close();
  if (!out) throw StreamError(path, "write failed");
}

std::string BaseName(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

void WritePgm(const MapView& map, const std::string& path, const MapFileOptions& options) {
  std::ofstream out = OpenOut(path);
  out << "P5\n# freespace map, " << Decimal(map.resolution_m) << " m/pixel\n"
      << map.width << ' ' << map.height << "\n255\n";
  std::vector<unsigned char> row(std::size_t(map.width));
  for (int r = map.height - 1; r >= 0; --r) {  // the image's first row is the map's northern
    for (int c = 0; c < map.width; ++c) {
      const LogOdds l = map.log_odds[std::size_t(r) * map.width + c];
      const double p = ProbabilityFromLogOdds(l);
      row[c] = l == 0 ? 205 : p > options.occupied_thresh ? 0 : p < options.free_thresh ? 254 : 205;
    }
    out.write(reinterpret_cast<const char*>(row.data()), std::streamsize(row.size()));
  }
  Finish(out, path);
}

void WriteYaml(const MapView& map, const MapFiles& files, const MapFileOptions& options) {
  std::ofstream out = OpenOut(files.yaml);
  out << "image: " << io::YamlQuoted(BaseName(files.pgm)) << "\n"
      << "resolution: " << Decimal(map.resolution_m) << "\n"
      << "origin: [" << Decimal(map.origin.x()) << ", " << Decimal(map.origin.y()) << ", "
      << Decimal(map.map_yaw) << "]\n"
      << "negate: 0\n"
      << "occupied_thresh: " << Decimal(options.occupied_thresh) << "\n"
      << "free_thresh: " << Decimal(options.free_thresh) << "\n"
      << "mode: trinary\n";
  Finish(out, files.yaml);
}

}  // namespace

std::int8_t OccupancyValue(LogOdds log_odds) {
  if (log_odds == 0) return -1;
  const long v = std::lround(100.0 * ProbabilityFromLogOdds(log_odds));
  return std::int8_t(std::clamp(v, 0L, 100L));
}

void FillOccupancyGrid(const MapView& map, std::int8_t* out) {
  CheckView(map, "FillOccupancyGrid");
  if (out == nullptr) throw std::invalid_argument("FillOccupancyGrid: null output");
  const std::size_t n = std::size_t(map.width) * std::size_t(map.height);
  for (std::size_t i = 0; i < n; ++i) out[i] = OccupancyValue(map.log_odds[i]);
}

std::vector<std::int8_t> OccupancyGrid(const MapView& map) {
  CheckView(map, "OccupancyGrid");
  std::vector<std::int8_t> values(std::size_t(map.width) * std::size_t(map.height));
  FillOccupancyGrid(map, values.data());
  return values;
}

void WriteNpyInt16(const std::string& path, const std::int16_t* data, int rows, int cols) {
  if (rows <= 0 || cols <= 0 || data == nullptr) {
    throw std::invalid_argument(path + ": WriteNpyInt16: empty array");
  }
  std::string header = "{'descr': '<i2', 'fortran_order': False, 'shape': (" +
                       std::to_string(rows) + ", " + std::to_string(cols) + "), }";
  // Magic (6) + version (2) + length (2) + header, padded with spaces to a multiple of 64 and
  // ended by a newline (the format's alignment rule).
  const std::size_t total = (10 + header.size() + 1 + 63) / 64 * 64;
  header.append(total - 10 - header.size() - 1, ' ');
  header += '\n';
  std::ofstream out = OpenOut(path);
  const unsigned char preamble[10] = {0x93,
                                      'N',
                                      'U',
                                      'M',
                                      'P',
                                      'Y',
                                      1,
                                      0,
                                      (unsigned char)(header.size() & 0xff),
                                      (unsigned char)(header.size() >> 8)};
  out.write(reinterpret_cast<const char*>(preamble), sizeof preamble);
  out << header;
  const std::size_t n = std::size_t(rows) * std::size_t(cols);
  std::vector<unsigned char> bytes(2 * n);
  for (std::size_t i = 0; i < n; ++i) {  // little-endian whatever the host
    const auto v = static_cast<std::uint16_t>(data[i]);
    bytes[2 * i] = static_cast<unsigned char>(v & 0xff);
    bytes[2 * i + 1] = static_cast<unsigned char>(v >> 8);
  }
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  Finish(out, path);
}

MapFiles MapFilesAt(const std::string& prefix) {
  return MapFiles{prefix + ".pgm", prefix + ".yaml", prefix + ".npy"};
}

MapFiles SaveMap(const MapView& map, const std::string& prefix, const MapFileOptions& options) {
  CheckView(map, "SaveMap");
  if (!(options.free_thresh > 0 && options.free_thresh < options.occupied_thresh &&
        options.occupied_thresh < 1)) {
    throw std::invalid_argument("SaveMap: need 0 < free_thresh (" + Decimal(options.free_thresh) +
                                ") < occupied_thresh (" + Decimal(options.occupied_thresh) +
                                ") < 1");
  }
  if (prefix.empty() || prefix.back() == '/') {
    throw std::invalid_argument("SaveMap: prefix '" + prefix + "' names no file");
  }
  const MapFiles files = MapFilesAt(prefix);
  WritePgm(map, files.pgm, options);
  WriteYaml(map, files, options);
  WriteNpyInt16(files.npy, map.log_odds, map.height, map.width);
  return files;
}

}  // namespace freespace
