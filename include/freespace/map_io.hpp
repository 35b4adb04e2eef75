// The map for other tools: nav_msgs/OccupancyGrid-style values (int8, 0..100, -1 unknown) and
// map files that ROS's map_server loads (PGM + YAML), with the raw log-odds as a NumPy .npy.
// Layout and thresholds: docs/formats.md, "Map files".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "freespace/result.hpp"

namespace freespace {

// A cell's occupancy as nav_msgs/OccupancyGrid holds it: round(100 p) in 0..100, or -1 where
// the cell is unknown (log-odds exactly 0: never observed, or observed to exactly p = 0.5).
std::int8_t OccupancyValue(LogOdds log_odds);

// Fills `out` (map.width * map.height values) with OccupancyValue of every cell, row-major,
// row 0 southern: the order of nav_msgs/OccupancyGrid's data, whose info.origin is map.origin
// (and yaw map.map_yaw). Throws std::invalid_argument for an empty view or a null `out`.
void FillOccupancyGrid(const MapView& map, std::int8_t* out);
std::vector<std::int8_t> OccupancyGrid(const MapView& map);

// How SaveMap writes a cell into the map_server image (its mode "trinary"): occupied (black, 0)
// where p > occupied_thresh, free (white, 254) where p < free_thresh, unknown (205) otherwise.
// map_server applies the same thresholds, written into the YAML, when it loads the image: the
// loaded map says occupied, free and unknown exactly where this map does. The defaults are
// map_server's map_saver's.
struct MapFileOptions {
  double occupied_thresh = 0.65;  // (free_thresh, 1)
  double free_thresh = 0.196;     // (0, occupied_thresh); the unknown gray 205 reads as 0.196
};

// The files SaveMap wrote.
struct MapFiles {
  std::string pgm;   // PREFIX.pgm: binary PGM (P5), 8 bits, first row northern
  std::string yaml;  // PREFIX.yaml: image, resolution, origin, negate, thresholds, mode
  std::string npy;   // PREFIX.npy: int16 log-odds (kLogOddsScale units), shape (height, width),
                     // row 0 southern like MapView
};

// The files SaveMap writes at `prefix`.
MapFiles MapFilesAt(const std::string& prefix);

// Writes the map as PREFIX.pgm + PREFIX.yaml (a map_server map) and PREFIX.npy. Throws
// std::invalid_argument for bad options, an empty view or a prefix that names no file (empty or
// ending in '/'), OutputError when a file cannot be written.
MapFiles SaveMap(const MapView& map, const std::string& prefix, const MapFileOptions& options = {});

// Writes a row-major int16 array as a NumPy .npy file (format 1.0, little-endian '<i2').
void WriteNpyInt16(const std::string& path, const std::int16_t* data, int rows, int cols);

}  // namespace freespace
