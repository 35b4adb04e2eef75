// The per-scan output lines of the command-line tools (docs/formats.md).
#pragma once

#include <cstdint>
#include <string>

#include "freespace/result.hpp"

namespace freespace {

// One line of polygons.jsonl (without the newline): scan index, time, pose, origin, vehicle,
// status and the polygon in world metres (a closed counter-clockwise ring, frame "world").
std::string PolygonJsonLine(std::uint64_t scan, const Result& result);

}  // namespace freespace
