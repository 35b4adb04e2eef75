// sensor_msgs/PointCloud2 into a multi-layer scan (cloud_cut.hpp).
#include "cloud_cut.hpp"

#include <sensor_msgs/PointField.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace freespace::ros_bag {
namespace {

using sensor_msgs::PointField;

int SizeOf(std::uint8_t type) {
  switch (type) {
    case PointField::INT8:
    case PointField::UINT8:
      return 1;
    case PointField::INT16:
    case PointField::UINT16:
      return 2;
    case PointField::INT32:
    case PointField::UINT32:
    case PointField::FLOAT32:
      return 4;
    case PointField::FLOAT64:
      return 8;
  }
  return 0;
}

const char* TypeName(std::uint8_t type) {
  static const char* const kNames[] = {"unknown", "int8",   "uint8",   "int16",  "uint16",
                                       "int32",   "uint32", "float32", "float64"};
  return type <= 8 ? kNames[type] : "unknown";
}

bool IsLittleEndianHost() {
  const std::uint16_t one = 1;
  std::uint8_t first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

// One field's value as a double, the bytes reversed first when the cloud's order is not ours.
template <typename T>
double Load(const std::uint8_t* p, bool swap) {
  std::uint8_t bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (swap) std::reverse(bytes, bytes + sizeof(T));
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return double(value);
}

double Value(const std::uint8_t* point, const CloudLayout::Field& f, bool swap) {
  const std::uint8_t* p = point + f.offset;
  switch (f.type) {
    case PointField::INT8:
      return Load<std::int8_t>(p, swap);
    case PointField::UINT8:
      return Load<std::uint8_t>(p, swap);
    case PointField::INT16:
      return Load<std::int16_t>(p, swap);
    case PointField::UINT16:
      return Load<std::uint16_t>(p, swap);
    case PointField::INT32:
      return Load<std::int32_t>(p, swap);
    case PointField::UINT32:
      return Load<std::uint32_t>(p, swap);
    case PointField::FLOAT32:
      return Load<float>(p, swap);
    case PointField::FLOAT64:
      return Load<double>(p, swap);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// Calls f(point bytes) for every point of the cloud, row by row.
template <typename F>
void ForEachPoint(const sensor_msgs::PointCloud2& cloud, F f) {
  for (std::uint32_t r = 0; r < cloud.height; ++r) {
    const std::uint8_t* row = cloud.data.data() + std::size_t(r) * cloud.row_step;
    for (std::uint32_t c = 0; c < cloud.width; ++c) f(row + std::size_t(c) * cloud.point_step);
  }
}

}  // namespace

std::string ReadLayout(const sensor_msgs::PointCloud2& cloud, CloudLayout* layout) {
  *layout = CloudLayout{};
  layout->swap = bool(cloud.is_bigendian) == IsLittleEndianHost();
  std::string fields;
  for (const PointField& f : cloud.fields) {
    fields += (fields.empty() ? "" : ", ") + f.name + " (" + TypeName(f.datatype) + ")";
    CloudLayout::Field* slot = f.name == "x"      ? &layout->x
                               : f.name == "y"    ? &layout->y
                               : f.name == "z"    ? &layout->z
                               : f.name == "ring" ? &layout->ring
                                                  : nullptr;
    if (slot == nullptr) continue;
    const int size = SizeOf(f.datatype);
    if (size == 0 || std::uint64_t(f.offset) + std::uint64_t(size) > cloud.point_step) {
      return "field " + f.name + " (" + TypeName(f.datatype) + " at byte " +
             std::to_string(f.offset) + ") does not fit a point of " +
             std::to_string(cloud.point_step) + " bytes";
    }
    *slot = {long(f.offset), f.datatype};
  }
  for (const CloudLayout::Field* f : {&layout->x, &layout->y, &layout->z}) {
    if (f->offset < 0 || (f->type != PointField::FLOAT32 && f->type != PointField::FLOAT64)) {
      return "needs float32 fields x, y and z; it has " + (fields.empty() ? "none" : fields);
    }
  }
  if (layout->ring.offset >= 0 &&
      (layout->ring.type == PointField::FLOAT32 || layout->ring.type == PointField::FLOAT64)) {
    layout->ring = {};
    layout->ring_not_integer = true;
  }
  const std::uint64_t row = std::uint64_t(cloud.width) * cloud.point_step;
  if (cloud.row_step < row || std::uint64_t(cloud.height) * cloud.row_step > cloud.data.size()) {
    return std::to_string(cloud.data.size()) + " bytes of data for " +
           std::to_string(cloud.height) + " rows of " + std::to_string(cloud.row_step) +
           " bytes (" + std::to_string(cloud.width) + " points of " +
           std::to_string(cloud.point_step) + " bytes)";
  }
  return "";
}

int RingLayers(const sensor_msgs::PointCloud2& cloud, const CloudLayout& layout) {
  if (layout.ring.offset < 0) return 0;
  double top = -1;
  ForEachPoint(cloud, [&](const std::uint8_t* p) {
    const double x = Value(p, layout.x, layout.swap), y = Value(p, layout.y, layout.swap);
    if (std::isfinite(x) && std::isfinite(y))
      top = std::max(top, Value(p, layout.ring, layout.swap));
  });
  return int(std::min(top + 1, 1e9));
}

void CutCloud(const sensor_msgs::PointCloud2& cloud, const CloudLayout& layout, bool by_ring,
              io::LayerCut* cut, std::vector<ScanPoint>* points, CloudCounts* counts) {
  *counts = CloudCounts{};
  cut->Clear();
  ForEachPoint(cloud, [&](const std::uint8_t* p) {
    ++counts->points;
    const double x = Value(p, layout.x, layout.swap), y = Value(p, layout.y, layout.swap),
                 z = Value(p, layout.z, layout.swap);
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      ++counts->not_finite;
      return;
    }
    if (!by_ring) {
      cut->Add(x, y, z);
      return;
    }
    const double ring = Value(p, layout.ring, layout.swap);
    if (ring < 0 || ring >= cut->layers()) {
      ++counts->ring_outside;
      return;
    }
    cut->AddOnLayer(int(ring), x, y);
  });
  cut->Fill(points);
}

}  // namespace freespace::ros_bag
