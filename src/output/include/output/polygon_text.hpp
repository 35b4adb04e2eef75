// The free-space polygon as files hold it: a closed, counter-clockwise ring (first vertex
// repeated at the end) in the world frame, and a scan's polygon as one GeoJSON Feature
// (RFC 7946) for newline-delimited GeoJSON (polygons.geojsonl, docs/formats.md).
#pragma once

#include <string>
#include <vector>

#include "freespace/result.hpp"

namespace freespace {

// The frame polygon coordinates are given in: the world frame of the input poses, metres.
inline constexpr const char* kPolygonFrame = "world";

// Appends `v` with `decimals` fixed decimals, or `null` when it is not finite (JSON has no NaN
// or infinity). Any finite double fits in fixed notation, so no number is ever cut.
void AppendJsonNumber(std::string* text, double v, int decimals);

// Appends {"x":..,"y":..,"yaw":..} with 6 decimals (AppendJsonNumber).
void AppendJsonPose(std::string* text, double x, double y, double yaw);

// `polygon` as a closed ring: counter-clockwise (reversed when its signed area is negative),
// the first vertex repeated at the end. Empty for an empty polygon.
std::vector<Vec2> ClosedCcwRing(const std::vector<Vec2>& polygon);

// "[[x,y],...]" with 4 decimals (0.1 mm), the ring as given (AppendJsonNumber).
std::string RingJson(const std::vector<Vec2>& ring);

// One GeoJSON Feature (one line, no newline): geometry a Polygon whose one ring is the closed
// counter-clockwise free-space polygon, or null when the scan has no polygon; properties scan,
// t_s, status, polygon_status, frame, pose and speed_mps.
std::string PolygonGeoJsonLine(const Result& result);

}  // namespace freespace
