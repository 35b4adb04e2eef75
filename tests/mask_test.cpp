// Kernel stage 3b: the polygon mask (polygon.shape inside), and the per-scan veto of stage 3.
// Hand-made maps for the margin's cone, and both backends against a cell-by-cell transcription
// of the rule on random maps, echoes and sensor positions.
#include <random>

#include "test_util.hpp"

namespace freespace {
namespace {

class MaskTest : public ::testing::TestWithParam<BackendKind> {};

struct Scene {
  int width = 0, height = 0;
  std::vector<LogOdds> map;
  std::vector<std::uint8_t> free;  // the free mask stage 3 would have made
  std::vector<std::int32_t> echoes;
  std::vector<std::int32_t> face_near, face_seen;  // the face layer (SetFaces)
  Vec2 sensor;
  std::vector<Vec2> scanners;  // the margin's lines of sight (none: from the sensor)
};

MarginViews ViewsOf(const Scene& s) {
  MarginViews views;
  if (s.scanners.empty()) views.Add(MakeSensorCell(s.sensor, s.width, s.height));
  for (const Vec2& v : s.scanners) views.Add(MakeSensorCell(v, s.width, s.height));
  return views;
}

// The polygon mask of `scene` as a backend makes it, one byte a cell.
std::vector<std::uint8_t> MaskOf(Backend& backend, const Scene& s) {
  backend.WriteLogOdds(s.map.data());
  backend.WriteFree(s.free.data());
  backend.SetEchoes(s.echoes.data(), int(s.echoes.size()));
  backend.SetFaces(s.face_near.data(), int(s.face_near.size()), s.face_seen.data(),
                   int(s.face_seen.size()));
  backend.Mask(MakeSensorCell(s.sensor, s.width, s.height), ViewsOf(s));
  const int words = (s.width + 63) / 64;
  std::vector<std::uint64_t> bits(std::size_t(words) * s.height, 0);
  backend.ReadMaskBits(0, s.height, bits.data());
  std::vector<std::uint8_t> mask(s.free.size());
  for (int r = 0; r < s.height; ++r) {
    for (int c = 0; c < s.width; ++c) {
      mask[std::size_t(r) * s.width + c] = (bits[std::size_t(r) * words + c / 64] >> (c % 64)) & 1;
    }
  }
  return mask;
}

// The rule of Backend::Mask, cell by cell.
std::vector<std::uint8_t> Expected(const Scene& s, const KernelParams& p) {
  const SensorCell sensor = MakeSensorCell(s.sensor, s.width, s.height);
  const MarginViews views = ViewsOf(s);
  std::vector<std::uint8_t> echo(s.free.size(), 0), mask(s.free.size(), 0);
  std::vector<std::uint8_t> near(s.free.size(), 0), seen(s.free.size(), 0);
  for (const std::int32_t c : s.echoes) echo[std::size_t(c)] = 1;
  for (const std::int32_t c : s.face_near) near[std::size_t(c)] = 1;
  for (const std::int32_t c : s.face_seen) seen[std::size_t(c)] = 1;
  const auto at = [&](int r, int c) { return std::size_t(r) * s.width + c; };
  for (int r = 0; r < s.height; ++r) {
    for (int c = 0; c < s.width; ++c) {
      const bool stands = std::abs(r - sensor.cell.row) <= p.opening_radius &&
                          std::abs(c - sensor.cell.col) <= p.opening_radius &&
                          s.map[at(r, c)] < 0 && !echo[at(r, c)];
      bool in = (s.free[at(r, c)] || stands) && !near[at(r, c)];
      for (int dy = -p.margin_cells; in && dy <= p.margin_cells; ++dy) {
        for (int dx = -p.margin_cells; in && dx <= p.margin_cells; ++dx) {
          const int rr = r + dy, cc = c + dx;
          if ((dx == 0 && dy == 0) || rr < 0 || cc < 0 || rr >= s.height || cc >= s.width) continue;
          const bool source = (s.map[at(rr, cc)] >= 0 || echo[at(rr, cc)]) && !seen[at(rr, cc)];
          for (int v = 0; v < views.count; ++v) {
            if (source && InMarginCone(p, views.x[v], views.y[v], c, r, dx, dy)) in = false;
          }
        }
      }
      mask[at(r, c)] = in || (r == sensor.cell.row && c == sensor.cell.col);
    }
  }
  return mask;
}

// A hand-made map as rows of text, the top line the northern row: '.' free, '#' occupied
// (log-odds above 0, not free), '?' unknown (log-odds 0, not free), 'e' an echo of this scan in a
// cell the map holds free, 'o' the sensor's cell (free), 'x' free but expected out of the mask.
Scene FromText(const std::vector<std::string>& rows, std::vector<std::uint8_t>* expected) {
  Scene s;
  s.height = int(rows.size());
  s.width = int(rows[0].size());
  s.free.assign(std::size_t(s.width) * s.height, 1);
  s.map.assign(s.free.size(), LogOdds{-100});
  *expected = s.free;
  for (int r = 0; r < s.height; ++r) {
    for (int c = 0; c < s.width; ++c) {
      const char t = rows[s.height - 1 - r][c];
      const std::size_t i = std::size_t(r) * s.width + c;
      if (t == '#') s.free[i] = (*expected)[i] = 0, s.map[i] = 100;
      if (t == '?') s.free[i] = (*expected)[i] = 0, s.map[i] = 0;
      if (t == 'e') s.free[i] = (*expected)[i] = 0, s.echoes.push_back(std::int32_t(i));
      if (t == 'x') (*expected)[i] = 0;
      if (t == 'o') s.sensor = Vec2(c + 0.5, r + 0.5);
    }
  }
  return s;
}

KernelParams MarginParams(int width, int height, int cells, double cone_deg) {
  Config config = test::SmallConfig(width, height);
  config.polygon.shape = PolygonShape::kInside;
  config.polygon.margin_cells = cells;
  config.polygon.margin_cone_deg = cone_deg;
  return MakeKernelParams(config);
}

TEST_P(MaskTest, MarginKeepsOutTheCellsInFrontOfAWallAsTheSensorSeesIt) {
  // A wall three rows north of the sensor: with a 60 deg cone the cells in front of it go;
  // those beside its ends (which see it at 90 deg or more) and those behind it stay. All around
  // (180 deg): every free cell within one cell of the wall. Two cells: two rows in front.
  const std::vector<std::pair<std::vector<std::string>, std::pair<int, double>>> cases = {
      {{".........", "..#####..", "..xxxxx..", ".........", ".........", "....o...."}, {1, 60}},
      {{".xxxxxxx.", ".x#####x.", ".xxxxxxx.", ".........", ".........", "....o...."}, {1, 180}},
      {{".........", "..#####..", "..xxxxx..", "..xxxxx..", ".........", "....o...."}, {2, 60}},
      // An echo of this scan counts as occupied, and is out of the mask itself.
      {{".........", "..eeeee..", "..xxxxx..", ".........", ".........", "....o...."}, {1, 60}},
      // So does a cell the map does not know (log-odds 0): what lies there was never seen.
      {{".........", "..?????..", "..xxxxx..", ".........", ".........", "....o...."}, {1, 60}},
  };
  for (const auto& [rows, margin] : cases) {
    std::vector<std::uint8_t> expected;
    const Scene s = FromText(rows, &expected);
    const KernelParams p = MarginParams(s.width, s.height, margin.first, margin.second);
    FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
    EXPECT_EQ(MaskOf(*backend, s), expected) << rows[1] << " k " << margin.first;
    EXPECT_EQ(Expected(s, p), expected) << rows[1] << " k " << margin.first;
  }
}

TEST_P(MaskTest, MarginFollowsTheLineOfSightOfEveryScannerOfARig) {
  // The rig's reference point 'o' south of a wall, its two scanners far to the west and east:
  // the cells in front of the wall as the reference sees it stay; those in front of its ends as
  // each scanner sees them (west of the wall's west end, east of its east end) go.
  std::vector<std::uint8_t> expected;
  Scene s = FromText(
      {"...........", "...........", "...x###x...", "...........", "...........", ".....o....."},
      &expected);
  s.scanners = {Vec2(-40.0, 3.5), Vec2(51.0, 3.5)};
  const KernelParams p = MarginParams(s.width, s.height, 1, 30);
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
  EXPECT_EQ(MaskOf(*backend, s), expected);
  EXPECT_EQ(Expected(s, p), expected);
  // With the reference point as the only line of sight, the row in front of the wall goes
  // instead.
  s.scanners.clear();
  const std::vector<std::uint8_t> alone = MaskOf(*backend, s);
  EXPECT_FALSE(alone[std::size_t(2) * s.width + 5]);
  EXPECT_TRUE(alone[std::size_t(3) * s.width + 3]);
}

TEST_P(MaskTest, TheSensorsOwnCellStays) {
  std::vector<std::uint8_t> expected;
  Scene s =
      FromText({"..........", "..........", ".....#....", "....o.....", ".........."}, &expected);
  s.free[std::size_t(1) * s.width + 4] = 0;  // even where stage 3 left it out
  const KernelParams p = MarginParams(s.width, s.height, 1, 180);
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
  const std::vector<std::uint8_t> mask = MaskOf(*backend, s);
  EXPECT_TRUE(mask[std::size_t(1) * s.width + 4]);
  EXPECT_EQ(mask, Expected(s, p));
}

TEST_P(MaskTest, MatchesTheRuleOnRandomMaps) {
  std::mt19937 rng(23);
  for (int trial = 0; trial < 60; ++trial) {
    Scene s;
    s.width = 20 + int(rng() % 150);
    s.height = 20 + int(rng() % 90);
    const std::size_t cells = std::size_t(s.width) * s.height;
    s.map.resize(cells);
    s.free.resize(cells);
    std::uniform_int_distribution<int> level(-300, 300), pick(0, 9);
    for (std::size_t i = 0; i < cells; ++i) {
      s.map[i] = LogOdds(pick(rng) < 6 ? 0 : level(rng));
      s.free[i] = s.map[i] < -80 && pick(rng) > 1;
    }
    for (int e = int(rng() % 60); e > 0; --e) s.echoes.push_back(std::int32_t(rng() % cells));
    for (int e = trial % 3 ? int(rng() % 200) : 0; e > 0; --e) {  // with every margin width
      s.face_near.push_back(std::int32_t(rng() % cells));
      if (rng() % 2) s.face_seen.push_back(s.face_near.back());
      if (rng() % 3 == 0)
        s.face_seen.push_back(s.echoes.empty() ? 0 : s.echoes[rng() % s.echoes.size()]);
    }
    std::uniform_real_distribution<double> x(0.0, s.width), y(0.0, s.height);
    s.sensor = Vec2(x(rng), y(rng));
    if (trial % 5 == 0) s.sensor = Vec2(std::floor(s.sensor.x()) + 0.5, std::floor(s.sensor.y()));
    for (int v = trial % 3 == 1 ? 1 + int(rng() % 4) : 0; v > 0; --v) {
      s.scanners.push_back(Vec2(x(rng), y(rng)));  // a rig's scanners
    }
    Config config = test::SmallConfig(s.width, s.height);
    config.polygon.shape = PolygonShape::kInside;
    config.polygon.margin_cells = trial % 4;
    config.polygon.margin_cone_deg = std::vector<double>{10, 30, 60, 90, 120, 180}[trial % 6];
    config.classify.vehicle_width_m = 0.2 * (trial % 7);
    const KernelParams p = MakeKernelParams(config);
    FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
    ASSERT_EQ(MaskOf(*backend, s), Expected(s, p)) << "trial " << trial;
  }
}

TEST_P(MaskTest, TheFaceLayerDecidesNearTheOutline) {
  // A wall's echoes in row 5, the face just below them touching those cells and keeping out the
  // free cells of row 4 under its middle: with faces, the wall's cells are no margin sources, so
  // the margin no longer takes the whole of row 4 and the sensor's side of the wall is kept but
  // for the face's own cells.
  std::vector<std::uint8_t> expected;
  Scene s = FromText({"??????????",  //
                      "eeeeeeeeee",  //
                      "..........",  //
                      "..........",  //
                      "..........",  //
                      "....o.....",  //
                      ".........."},
                     &expected);
  const KernelParams p = MarginParams(s.width, s.height, 1, 180);
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
  const std::vector<std::uint8_t> margin_only = MaskOf(*backend, s);
  const int wall = 5;
  for (int c = 0; c < s.width; ++c) EXPECT_FALSE(margin_only[std::size_t(wall - 1) * s.width + c]);
  for (int c = 0; c < s.width; ++c) s.face_seen.push_back(wall * s.width + c);
  for (int c = 3; c < 7; ++c) s.face_near.push_back((wall - 1) * s.width + c);
  const std::vector<std::uint8_t> mask = MaskOf(*backend, s);
  for (int c = 0; c < s.width; ++c) {
    EXPECT_EQ(mask[std::size_t(wall - 1) * s.width + c], c < 3 || c >= 7) << "col " << c;
  }
  EXPECT_EQ(mask, Expected(s, p));
}

TEST_P(MaskTest, VetoTakesThisScansEchoesOutOfTheFreeMask) {
  // A map free everywhere: the cells of this scan's echoes are not free with the veto, are with
  // it off, and the next scan's echoes replace them.
  const int width = 70, height = 40;
  std::vector<LogOdds> map(std::size_t(width) * height, LogOdds{-300});
  const std::vector<std::int32_t> first = {5 * width + 7, 5 * width + 8, 30 * width + 69};
  const std::vector<std::int32_t> second = {12 * width + 40};
  for (const bool veto : {true, false}) {
    Config config = test::SmallConfig(width, height);
    config.classify.veto_current_echoes = veto;
    FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), MakeKernelParams(config));
    backend->WriteLogOdds(map.data());
    std::vector<std::uint8_t> free(map.size());
    for (const auto& echoes : {first, second}) {
      backend->SetEchoes(echoes.data(), int(echoes.size()));
      backend->Classify();
      backend->ReadFree(free.data());
      for (std::size_t i = 0; i < free.size(); ++i) {
        const bool echo = std::find(echoes.begin(), echoes.end(), std::int32_t(i)) != echoes.end();
        ASSERT_EQ(free[i], veto && echo ? 0 : 1) << "veto " << veto << " cell " << i;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, MaskTest, ::testing::ValuesIn(test::AllBackends()),
                         test::BackendParamName);

}  // namespace
}  // namespace freespace
