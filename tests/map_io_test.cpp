// Map files for other tools: OccupancyGrid values (0..100, -1 unknown) cell by cell, and the
// map_server PGM + YAML and the .npy that SaveMap writes, read back byte by byte: the YAML's
// keys and values, the PGM's header and its rows (first row northern), the .npy's header and
// its little-endian int16 data (row 0 southern).
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/backend.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A 3-column, 2-row map: row 0 (south) = occupied, unknown, free; row 1 = slightly free,
// slightly occupied, strongly free.
struct SmallMap {
  std::vector<LogOdds> cells = {LogOddsFromProbability(0.9), 0,
                                LogOddsFromProbability(0.1), LogOddsFromProbability(0.45),
                                LogOddsFromProbability(0.7), LogOddsFromProbability(0.02)};
  MapView View() const {
    MapView v;
    v.width = 3;
    v.height = 2;
    v.resolution_m = 0.2;
    v.origin = Vec2(-100000.3, 42.2);
    v.log_odds = cells.data();
    return v;
  }
};

TEST(MapIo, OccupancyValuesAreRoundedPercentAndMinusOneForUnknown) {
  SmallMap m;
  const std::vector<std::int8_t> grid = OccupancyGrid(m.View());
  EXPECT_EQ(grid, (std::vector<std::int8_t>{90, -1, 10, 45, 70, 2}));
  EXPECT_EQ(OccupancyValue(1), 50);  // the smallest step off unknown is known, p ~ 0.501
  EXPECT_EQ(OccupancyValue(32767), 100);
  EXPECT_EQ(OccupancyValue(-32767), 0);
  EXPECT_THROW(FillOccupancyGrid(m.View(), nullptr), std::invalid_argument);
  EXPECT_THROW(OccupancyGrid(MapView{}), std::invalid_argument);
}

class MapFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(::testing::TempDir()) / "freespace_map_io";
    std::filesystem::create_directories(dir_);
    files_ = SaveMap(map_.View(), (dir_ / "map").string());
  }
  SmallMap map_;
  std::filesystem::path dir_;
  MapFiles files_;
};

TEST_F(MapFilesTest, YamlHasEveryMapServerKey) {
  const YAML::Node yaml = YAML::LoadFile(files_.yaml);
  for (const char* key :
       {"image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh", "mode"}) {
    EXPECT_TRUE(yaml[key]) << "missing " << key;
  }
  EXPECT_EQ(yaml.size(), 7u) << "keys map_server does not know";
  EXPECT_EQ(yaml["image"].as<std::string>(), "map.pgm");  // relative to the YAML
  EXPECT_EQ(yaml["resolution"].as<double>(), 0.2);
  ASSERT_EQ(yaml["origin"].size(), 3u);
  EXPECT_EQ(yaml["origin"][0].as<double>(), -100000.3);  // exact: written to round-trip
  EXPECT_EQ(yaml["origin"][1].as<double>(), 42.2);
  EXPECT_EQ(yaml["origin"][2].as<double>(), 0.0);
  EXPECT_EQ(yaml["negate"].as<int>(), 0);
  EXPECT_EQ(yaml["occupied_thresh"].as<double>(), 0.65);
  EXPECT_EQ(yaml["free_thresh"].as<double>(), 0.196);
  EXPECT_EQ(yaml["mode"].as<std::string>(), "trinary");
}

// The image's name as written, whatever it holds: a '#' (a comment to YAML), ": ", quotes, a
// backslash, a tab.
TEST_F(MapFilesTest, TheImageNameReadsBackWhateverItHolds) {
  for (const std::string name : {"#1 map", "a: b", "say \"hi\"", "back\\slash", "tab\there"}) {
    const MapFiles files = SaveMap(map_.View(), (dir_ / name).string());
    const YAML::Node yaml = YAML::LoadFile(files.yaml);
    EXPECT_EQ(yaml["image"].as<std::string>(), name + ".pgm") << ReadAll(files.yaml);
    EXPECT_TRUE(std::filesystem::exists(dir_ / (name + ".pgm")));
  }
}

TEST_F(MapFilesTest, PgmIsBinaryEightBitNorthFirst) {
  const std::string pgm = ReadAll(files_.pgm);
  const std::string header = "P5\n# freespace map, 0.2 m/pixel\n3 2\n255\n";
  ASSERT_EQ(pgm.substr(0, header.size()), header);
  const std::string pixels = pgm.substr(header.size());
  // Row 1 (north) first: p 0.45 unknown gray, 0.7 occupied, 0.02 free; then row 0 (south):
  // 0.9 occupied, log-odds 0 unknown, 0.1 free.
  const std::string expected = {char(205), char(0), char(254), char(0), char(205), char(254)};
  EXPECT_EQ(pixels, expected);
}

TEST_F(MapFilesTest, MapServerReadsBackTheOccupancyThresholds) {
  // map_server's trinary load: p = (255 - pixel) / 255; occupied when p > occupied_thresh, free
  // when p < free_thresh, else unknown. Read back, each cell agrees with the grid's thresholds.
  const std::string pgm = ReadAll(files_.pgm);
  const std::string pixels = pgm.substr(pgm.size() - 6);
  const std::vector<std::int8_t> grid = OccupancyGrid(map_.View());
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 3; ++c) {
      const double p = (255.0 - double(static_cast<unsigned char>(pixels[(1 - r) * 3 + c]))) / 255;
      const int loaded = p > 0.65 ? 100 : p < 0.196 ? 0 : -1;
      const int value = grid[r * 3 + c];
      const int expected = value > 65 ? 100 : (value >= 0 && value < 19.6) ? 0 : -1;
      EXPECT_EQ(loaded, expected) << "row " << r << " col " << c << " value " << value;
    }
  }
}

TEST_F(MapFilesTest, NpyHoldsTheRawLogOddsRowZeroSouth) {
  const std::string npy = ReadAll(files_.npy);
  ASSERT_GE(npy.size(), 10u);
  EXPECT_EQ(npy.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const std::size_t header_len =
      static_cast<unsigned char>(npy[8]) | (static_cast<unsigned char>(npy[9]) << 8);
  EXPECT_EQ((10 + header_len) % 64, 0u) << "header not aligned to 64 bytes";
  const std::string header = npy.substr(10, header_len);
  EXPECT_EQ(header.rfind("{'descr': '<i2', 'fortran_order': False, 'shape': (2, 3), }", 0), 0u)
      << header;
  EXPECT_EQ(header.back(), '\n');
  ASSERT_EQ(npy.size(), 10 + header_len + 2 * 6);
  for (int i = 0; i < 6; ++i) {
    const auto lo = static_cast<unsigned char>(npy[10 + header_len + 2 * i]);
    const auto hi = static_cast<unsigned char>(npy[10 + header_len + 2 * i + 1]);
    EXPECT_EQ(static_cast<std::int16_t>(lo | (hi << 8)), map_.cells[i]) << "cell " << i;
  }
}

TEST(MapIo, BadThresholdsAndUnwritablePathsThrow) {
  SmallMap m;
  MapFileOptions bad;
  bad.free_thresh = 0.7;
  EXPECT_THROW(SaveMap(m.View(), ::testing::TempDir() + "/x", bad), std::invalid_argument);
  EXPECT_THROW(SaveMap(m.View(), "/nonexistent-dir/for/sure/map"), OutputError);
  // A prefix that names no file: it would write hidden files .pgm, .yaml and .npy.
  EXPECT_THROW(SaveMap(m.View(), ::testing::TempDir() + "/"), std::invalid_argument);
  EXPECT_THROW(SaveMap(m.View(), ""), std::invalid_argument);
}

}  // namespace
}  // namespace freespace
