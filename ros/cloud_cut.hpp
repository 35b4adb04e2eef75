// sensor_msgs/PointCloud2 as a ScaLa-like multi-layer scan: the fields x, y, z (float32 or
// float64) and an optional integer `ring` field are found by name, the bytes read in the
// message's byte order, and every finite point goes through the layer cut shared with the
// KITTI reader (core/layer_cut.hpp): by ring (ring r is layer r) or by elevation.
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include <string>
#include <vector>

#include "core/layer_cut.hpp"
#include "freespace/scan.hpp"

namespace freespace::ros_bag {

// Where the fields of a cloud's points are. A field is absent with offset -1.
struct CloudLayout {
  struct Field {
    long offset = -1;
    std::uint8_t type = 0;  // sensor_msgs::PointField datatype
  };
  Field x, y, z, ring;
  bool swap = false;              // the data's byte order is not this machine's
  bool ring_not_integer = false;  // a ring field of float type, left out (layers by elevation)
};

// The layout of `cloud`, or "" plus why it cannot be read as a scan (x, y or z missing or not
// a float, a field past the point's end, data shorter than width x height points).
std::string ReadLayout(const sensor_msgs::PointCloud2& cloud, CloudLayout* layout);

// The layers a ring cut needs: the largest ring of a finite point + 1, 0 without one.
int RingLayers(const sensor_msgs::PointCloud2& cloud, const CloudLayout& layout);

// What a cut left out of one cloud.
struct CloudCounts {
  std::size_t points = 0, not_finite = 0, ring_outside = 0;
};

// Cuts `cloud` (whose layout ReadLayout accepted) into `points`: by its ring field when
// `by_ring` (points whose ring is not a layer of `cut` are counted in ring_outside), else by
// elevation. NaN and infinite points (an organized cloud's beams without return) are counted.
void CutCloud(const sensor_msgs::PointCloud2& cloud, const CloudLayout& layout, bool by_ring,
              io::LayerCut* cut, std::vector<ScanPoint>* points, CloudCounts* counts);

}  // namespace freespace::ros_bag
