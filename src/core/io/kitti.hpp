// What the KITTI readers share (kitti.cpp: one Velodyne frame; kitti_sequence.cpp: an odometry
// benchmark sequence folder): the sensor the cut makes and the cut of one frame file.
#pragma once

#include <string>
#include <vector>

#include "core/layer_cut.hpp"
#include "freespace/io.hpp"

namespace freespace::io {

// The ScaLa-like sensor of a KITTI cut: the ScaLa aperture and resolution, one layer per
// configured elevation, 1 .. 120 m (the HDL-64E; closer returns are the car itself). Throws
// InputError naming `path` and the LogOptions field when the cut is not valid.
SensorConfig KittiSensor(const LogOptions& options, const std::string& path);

// Adds every record of the Velodyne frame `path` (float32 x y z reflectance) to `cut`, reading
// it in chunks. Returns false when the file cannot be opened; what it had to ignore (a size
// that is not whole records, non-finite coordinates, coordinates beyond 1 km) and a frame that
// gives no point (an empty file, no point in any layer) go to `problems`.
bool CutVelodyneFrame(const std::string& path, LayerCut* cut, std::vector<std::string>* problems);

}  // namespace freespace::io
