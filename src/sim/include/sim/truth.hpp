// The exact truth of a simulated drive (docs/formats.md, "Truth file"): the world's obstacles,
// the scanner model, and per scan the true vehicle and sensor poses, the odometry pose the log
// holds and where every moving obstacle was. Written as JSON next to the logs; read back by
// `freespace eval`.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "freespace/types.hpp"
#include "sim/odometry.hpp"
#include "sim/rig.hpp"
#include "sim/scanner.hpp"
#include "sim/world.hpp"

namespace freespace::sim {

struct TruthScan {
  std::uint64_t index = 0;
  double t = 0.0;
  Pose2D pose;                 // true vehicle pose (reference point) at t
  Pose2D odometry;             // the pose the log holds for this scan
  Pose2D sensor;               // true sensor pose at t (a rig: its reference point's)
  double speed = 0.0;          // true speed, m/s, negative reversing
  std::vector<Pose2D> movers;  // pose of each moving obstacle at t
};

struct Truth {
  std::string scenario;
  std::string description;
  std::uint64_t seed = 0;
  ScannerConfig scanner;  // a rig: its first scanner
  Rig rig;                // the scanners of the drive; "front": `scanner` alone
  OdometryNoise odometry_noise;
  World world;  // read back: tracks empty, the movers' poses are in the scans
  std::vector<TruthScan> scans;
};

// Writes a truth file scan by scan, so that memory does not grow with the drive: the header
// (everything but the scans) on construction, each scan on Add(), the end on Close(). The file
// holds the same bytes as WriteTruth() of the whole drive. Throws OutputError when the file
// cannot be created or a write fails.
class TruthWriter {
 public:
  TruthWriter(const std::string& path, const Truth& header);  // header.scans is not written
  void Add(const TruthScan& scan);
  void Close();  // without it the file stays incomplete (not valid JSON)

 private:
  void Check();

  std::string path_;
  std::ofstream out_;
  std::string tail_;  // the document after the scans
  std::size_t scans_ = 0;
  bool closed_ = false;
};

// WriteTruth throws OutputError when the file cannot be written; ReadTruth throws InputError
// when it cannot be read or is not a truth file.
void WriteTruth(const std::string& path, const Truth& truth);
Truth ReadTruth(const std::string& path);

// The rigid transform that takes the true world into the frame the estimator's map is built
// in (the odometry frame) so that the vehicle's true pose lands on its odometry pose at this
// scan: odometry o true^-1. Identity when the odometry is exact.
Pose2D TruthToMapFrame(const TruthScan& scan);

}  // namespace freespace::sim
