// Preprocessing: validation of every bad point, the nearest return across layers, virtual
// points, and the projection into fixed-point map coordinates.
#include "core/preprocess.hpp"

#include "test_util.hpp"

namespace freespace {
namespace {

Config OneDegreeSensor() {
  Config c;
  c.sensor.layers = 2;
  c.sensor.min_angle_deg = -10;
  c.sensor.max_angle_deg = 10;
  c.sensor.angular_resolution_deg = 1;
  c.sensor.max_range_m = 50;
  c.clutter.enabled = false;
  return c;
}

ScanPoint Point(int layer, double deg, double range, bool echo = true) {
  ScanPoint p;
  p.layer = std::uint8_t(layer);
  p.angle_rad = float(deg * M_PI / 180.0);
  p.range_m = float(range);
  p.echo = echo;
  return p;
}

TEST(Preprocess, NearestReturnOfAnyLayerPerBin) {
  Preprocessor pre(OneDegreeSensor());
  Scan scan;
  scan.points = {Point(0, 0, 7.0), Point(1, 0, 4.0), Point(0, 1, 6.0), Point(1, 1, 9.0)};
  ScanStats stats;
  ASSERT_TRUE(pre.Run(scan, &stats));
  ASSERT_EQ(pre.beams().size(), 2u);
  EXPECT_FLOAT_EQ(pre.beams()[0].range, 4.0f);
  EXPECT_FLOAT_EQ(pre.beams()[1].range, 6.0f);
  EXPECT_EQ(stats.kept, 4);  // every kept echo is occupied, not only the nearest
}

TEST(Preprocess, VirtualPointsTakeTheNearerRealNeighbour) {
  Preprocessor pre(OneDegreeSensor());
  Scan scan;
  // bins: -3 none | -2 real 5 | -1 none | 0 none | 1 real 3 | 2 none
  scan.points = {Point(0, -3, 0, false), Point(0, -2, 5), Point(0, -1, 0, false),
                 Point(0, 0, 0, false),  Point(0, 1, 3),  Point(0, 2, 0, false)};
  ScanStats stats;
  ASSERT_TRUE(pre.Run(scan, &stats));
  const auto& b = pre.beams();
  ASSERT_EQ(b.size(), 6u);
  EXPECT_TRUE(b[0].is_virtual);
  EXPECT_FLOAT_EQ(b[0].range, 5.0f);  // edge: the one neighbour
  EXPECT_FLOAT_EQ(b[2].range, 3.0f);  // min(5, 3)
  EXPECT_FLOAT_EQ(b[3].range, 3.0f);
  EXPECT_FLOAT_EQ(b[5].range, 3.0f);  // edge
  EXPECT_FALSE(b[1].is_virtual);
  EXPECT_EQ(stats.virtual_points, 4);
  EXPECT_EQ(stats.no_echo, 4);
}

TEST(Preprocess, EveryBadPointIsCountedAndNoneIsOccupied) {
  Preprocessor pre(OneDegreeSensor());
  Scan scan;
  scan.points = {
      Point(0, 0, 5.0),                                       // good
      Point(0, 1, std::nan("")),                              // NaN: invalid, used as no echo
      Point(0, 2, -1.0),                                      // negative: invalid
      Point(0, 3, -std::numeric_limits<double>::infinity()),  // -inf: invalid
      Point(0, 4, std::numeric_limits<double>::infinity()),   // +inf: no echo
      Point(0, 5, 50.0),                                      // at max range: no echo
      Point(0, 6, 0.05),                                      // below min range: invalid
      Point(0, 45, 5.0),                                      // outside the aperture: dropped
      Point(0, std::nan(""), 5.0),                            // no angle: dropped
      Point(7, 0, 5.0),                                       // layer 7 of 2: dropped
  };
  ScanStats stats;
  ASSERT_TRUE(pre.Run(scan, &stats));
  EXPECT_EQ(stats.points, 10);
  EXPECT_EQ(stats.invalid_range, 4);
  EXPECT_EQ(stats.no_echo, 2);
  EXPECT_EQ(stats.out_of_aperture, 2);
  EXPECT_EQ(stats.bad_layer, 1);
  EXPECT_EQ(stats.kept, 1);
  EXPECT_EQ(stats.beams, 7);  // bins 0 .. 6 had beams
  for (std::size_t i = 1; i < pre.beams().size(); ++i) {
    EXPECT_TRUE(pre.beams()[i].is_virtual);
    EXPECT_FLOAT_EQ(pre.beams()[i].range, 5.0f);
  }
}

TEST(Preprocess, NoRealReturnMakesNoUpdate) {
  Preprocessor pre(OneDegreeSensor());
  ScanStats stats;
  Scan empty;
  EXPECT_FALSE(pre.Run(empty, &stats));
  Scan dark;
  dark.points = {Point(0, 0, 0, false), Point(1, 1, 0, false)};
  EXPECT_FALSE(pre.Run(dark, &stats));
  EXPECT_EQ(stats.no_echo, 2);
}

TEST(Preprocess, ProjectsIntoFixedPointCells) {
  Config c = OneDegreeSensor();
  Preprocessor pre(c);
  Scan scan;
  scan.points = {Point(0, 0, 1.0)};  // 1 m straight ahead = 5 cells at 0.2 m
  ScanStats stats;
  ASSERT_TRUE(pre.Run(scan, &stats));
  RasterJob job;
  pre.Project(Vec2(10.5, 10.5), M_PI / 2, 300, 300, &job);  // facing +y
  ASSERT_EQ(job.vertex_count, 2);
  EXPECT_EQ(job.vertices[0], 10 * 256 + 128);
  EXPECT_EQ(job.vertices[1], 10 * 256 + 128);
  EXPECT_EQ(job.vertices[2], 10 * 256 + 128);
  EXPECT_EQ(job.vertices[3], 15 * 256 + 128);
  ASSERT_EQ(job.occupied_count, 1);
  EXPECT_EQ(job.occupied[0], 15 * 300 + 10);
  EXPECT_EQ(job.row_begin, 10);
  EXPECT_EQ(job.row_end, 16);
}

}  // namespace
}  // namespace freespace
