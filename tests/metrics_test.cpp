// The quality metrics on small hand-made cases whose values are computed by hand: a 4 x 4 map
// of 1 m cells with one obstacle, hand-drawn polygons, a seen area that moves with the map,
// and the summary's pooled ratios; then the simulator and the estimator end to end, scored
// in process and from the written log and truth, which must agree exactly.
#include "eval/metrics.hpp"

#include <cmath>
#include <filesystem>

#include "eval/scorer.hpp"
#include "sim/simulator.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

using geometry::Box;
using geometry::Polygon;

// A 4 x 4 map of 1 m cells with its corner at the world origin. Rows are listed north first
// (as the map is drawn); F observed free (log-odds -100), O observed occupied (+100), . unknown.
struct HandMap {
  std::vector<LogOdds> log_odds;
  std::vector<std::uint8_t> free;
  MapView view;

  explicit HandMap(const std::vector<std::string>& rows_north_first, Vec2 origin = {0, 0}) {
    log_odds.assign(16, 0);
    free.assign(16, 0);
    for (int i = 0; i < 4; ++i) {
      const int row = 3 - i;
      for (int col = 0; col < 4; ++col) {
        const char c = rows_north_first[i][col];
        log_odds[row * 4 + col] = c == 'F' ? -100 : c == 'O' ? 100 : 0;
        free[row * 4 + col] = c == 'F' ? 1 : 0;
      }
    }
    view.width = view.height = 4;
    view.resolution_m = 1.0;
    view.origin = origin;
    view.log_odds = log_odds.data();
    view.free = free.data();
  }
};

geometry::Polygon WholeMap() { return Box(-10, -10, 10, 10); }

TEST(Metrics, CellAccuracyAndFalseFreeByHand) {
  // One obstacle: the square [1.25, 1.75]^2 inside cell (row 1, col 1). Its neighbours only
  // touch nothing: they are truly free.
  TruthFrame truth;
  truth.obstacles = {Box(1.25, 1.25, 1.75, 1.75)};
  truth.visible = WholeMap();
  {
    // The map gets the obstacle right and calls cell (2, 2) occupied by mistake; (3, 3) unknown.
    HandMap map({"FFF.",  //
                 "FFOF",  //
                 "FOFF",  //
                 "FFFF"});
    QualityEvaluator evaluator;
    const ScanMetrics m = evaluator.Evaluate(map.view, {}, truth);
    EXPECT_EQ(m.observed, 15);
    EXPECT_EQ(m.observed_occupied, 1);
    EXPECT_EQ(m.correct, 14);
    EXPECT_DOUBLE_EQ(m.accuracy, 14.0 / 15.0);
    EXPECT_EQ(m.false_free, 0);
    EXPECT_DOUBLE_EQ(m.false_free_rate, 0.0);
    EXPECT_EQ(m.false_occupied, 1);
    EXPECT_EQ(m.errors_at_border, 1);  // (2, 2) touches the obstacle's cell (1, 1)
    EXPECT_EQ(evaluator.covered_fraction()[1 * 4 + 1], 0.25f);
    EXPECT_EQ(evaluator.covered_fraction()[1 * 4 + 2], 0.0f);
  }
  {
    // The map calls the obstacle's cell free: one false-free cell of one, covered a quarter.
    HandMap map({"FFF.",  //
                 "FFFF",  //
                 "FFFF",  //
                 "FFFF"});
    QualityEvaluator evaluator;
    const ScanMetrics m = evaluator.Evaluate(map.view, {}, truth);
    EXPECT_EQ(m.correct, 14);
    EXPECT_EQ(m.false_free, 1);
    EXPECT_EQ(m.false_free_majority, 0);
    EXPECT_DOUBLE_EQ(m.false_free_rate, 1.0);
    EXPECT_EQ(m.false_free_mask, 1);
    EXPECT_EQ(m.false_free_moving, 0);
    truth.moving = {true};
    EXPECT_EQ(QualityEvaluator().Evaluate(map.view, {}, truth).false_free_moving, 1);
    const ScanMetrics moving =
        QualityEvaluator().Evaluate(map.view, Box(0.5, 0.5, 1.5, 1.5), truth);
    EXPECT_DOUBLE_EQ(moving.intrusion_moving_m2, 0.25);
    EXPECT_DOUBLE_EQ(moving.intrusion_mask_m2, 0.25);  // the mask calls that cell free
  }
  {
    // An obstacle whose edges lie exactly on cell borders covers its cell only.
    TruthFrame exact;
    exact.obstacles = {Box(1, 1, 2, 2)};
    exact.visible = WholeMap();
    HandMap map({"FFFF",  //
                 "FFFF",  //
                 "FOFF",  //
                 "FFFF"});
    const ScanMetrics m = QualityEvaluator().Evaluate(map.view, {}, exact);
    EXPECT_EQ(m.observed_occupied, 1);
    EXPECT_DOUBLE_EQ(m.accuracy, 1.0);
  }
}

TEST(Metrics, PolygonIntrusionAndCoverageByHand) {
  TruthFrame truth;
  truth.obstacles = {Box(1.25, 1.25, 1.75, 1.75)};
  truth.visible = WholeMap();
  truth.in_sight = WholeMap();
  HandMap map({"FFF.",  //
               "FFFF",  //
               "FOFF",  //
               "FFFF"});
  {
    // The polygon [0.5, 2.5]^2 (4 m^2) holds cell (1, 1) whole: intrusion 1 m^2 on truly
    // occupied cells, 0.25 m^2 on the obstacle itself. Reference: the 14 observed, truly free
    // cells in sight (16 less the obstacle's and the unknown one), 14 m^2; the polygon covers
    // 4 - 1 of them: coverage 3 / 14. All of them have been seen: the same over the seen area.
    const std::vector<Vec2> polygon = Box(0.5, 0.5, 2.5, 2.5);
    const ScanMetrics m = QualityEvaluator().Evaluate(map.view, polygon, truth);
    EXPECT_DOUBLE_EQ(m.polygon_area_m2, 4.0);
    EXPECT_DOUBLE_EQ(m.intrusion_m2, 1.0);
    EXPECT_DOUBLE_EQ(m.intrusion_geometric_m2, 0.25);
    EXPECT_DOUBLE_EQ(m.intrusion_mask_m2, 0.0);  // the free mask leaves cell (1, 1) out
    EXPECT_DOUBLE_EQ(m.reference_free_m2, 14.0);
    EXPECT_DOUBLE_EQ(m.covered_free_m2, 3.0);
    EXPECT_DOUBLE_EQ(m.coverage, 3.0 / 14.0);
    EXPECT_DOUBLE_EQ(m.reference_seen_m2, 14.0);
    EXPECT_DOUBLE_EQ(m.coverage_seen, 3.0 / 14.0);
    EXPECT_DOUBLE_EQ(m.reference_in_mask_m2, 14.0);  // the free mask holds every reference cell
    EXPECT_DOUBLE_EQ(m.coverage_mask, 1.0);
    // Two reference cells the map calls free but the free mask leaves out (the opening, say):
    // the reference stays, the mask's share falls to 12 / 14 whatever the polygon.
    HandMap opened = map;
    opened.view.log_odds = opened.log_odds.data();
    opened.view.free = opened.free.data();
    opened.free[0] = opened.free[1] = 0;
    const ScanMetrics o = QualityEvaluator().Evaluate(opened.view, polygon, truth);
    EXPECT_DOUBLE_EQ(o.reference_free_m2, 14.0);
    EXPECT_DOUBLE_EQ(o.reference_in_mask_m2, 12.0);
    EXPECT_DOUBLE_EQ(o.coverage_mask, 12.0 / 14.0);
    // No in-sight polygon given: coverage is not scored; the seen-so-far one still is.
    TruthFrame blind = truth;
    blind.in_sight.clear();
    const ScanMetrics b = QualityEvaluator().Evaluate(map.view, polygon, blind);
    EXPECT_TRUE(std::isnan(b.coverage));
    EXPECT_TRUE(std::isnan(b.coverage_mask));
    EXPECT_DOUBLE_EQ(b.coverage_seen, 3.0 / 14.0);
    EXPECT_TRUE(std::isnan(m.coverage_star));  // no centre given
  }
  {
    // Star-shaped around (0.5, 0.7): the occupied cell (1, 1) hides the centres of (1, 2),
    // (1, 3), (2, 1), (2, 2), (2, 3) and (3, 2) (row, col) from it; 8 of the 14 reference
    // cells remain, 9 when the polygon covers one hidden cell whole: it reached it.
    const Vec2 centre(0.5, 0.7);
    const ScanMetrics none = QualityEvaluator().Evaluate(map.view, {}, truth, centre);
    EXPECT_DOUBLE_EQ(none.reference_star_m2, 8.0);
    EXPECT_DOUBLE_EQ(none.coverage_star, 8.0 / 14.0);
    const ScanMetrics one = QualityEvaluator().Evaluate(map.view, Box(2, 1, 3, 2), truth, centre);
    EXPECT_DOUBLE_EQ(one.reference_star_m2, 9.0);
  }
  {
    // A polygon covering a quarter of the obstacle's cell: [0.5, 1.5]^2. Intrusion 0.25 m^2 on
    // the cell, 0.0625 m^2 on the obstacle ([1.25, 1.5]^2).
    const std::vector<Vec2> polygon = Box(0.5, 0.5, 1.5, 1.5);
    const ScanMetrics m = QualityEvaluator().Evaluate(map.view, polygon, truth);
    EXPECT_DOUBLE_EQ(m.intrusion_m2, 0.25);
    EXPECT_DOUBLE_EQ(m.intrusion_geometric_m2, 0.0625);
    EXPECT_DOUBLE_EQ(m.covered_free_m2, 0.75);
  }
  {
    // A hand-drawn concave polygon, clockwise (the metrics take either orientation): the L
    // (0,0) (3,0) (3,1) (1,1) (1,3) (0,3), area 5, avoiding cell (1, 1) but for its corner.
    std::vector<Vec2> polygon = {{0, 3}, {1, 3}, {1, 1}, {3, 1}, {3, 0}, {0, 0}};
    const ScanMetrics m = QualityEvaluator().Evaluate(map.view, polygon, truth);
    EXPECT_DOUBLE_EQ(m.polygon_area_m2, 5.0);
    EXPECT_DOUBLE_EQ(m.intrusion_m2, 0.0);
    EXPECT_DOUBLE_EQ(m.covered_free_m2, 5.0);
    EXPECT_DOUBLE_EQ(m.coverage, 5.0 / 14.0);
    // In sight now: only the western half (x < 2): 7 reference cells, of which the L covers
    // column 0 (rows 0 .. 2) and cell (0, 1): 4 m^2. The seen area is still the whole map.
    TruthFrame half = truth;
    half.in_sight = Box(0, 0, 2, 4);
    const ScanMetrics h = QualityEvaluator().Evaluate(map.view, polygon, half);
    EXPECT_DOUBLE_EQ(h.reference_free_m2, 7.0);
    EXPECT_DOUBLE_EQ(h.covered_free_m2, 4.0);
    EXPECT_DOUBLE_EQ(h.coverage, 4.0 / 7.0);
    EXPECT_DOUBLE_EQ(h.reference_seen_m2, 14.0);
    EXPECT_DOUBLE_EQ(h.coverage_seen, 5.0 / 14.0);
  }
}

// A scanner's visibility polygon: the scanner at `at`, then its beams' ends 10 m out from
// bearing `first_deg` on to `last_deg` (counter-clockwise), as the simulator writes it.
Polygon Fan(Vec2 at, double first_deg, double last_deg) {
  Polygon p = {at};
  for (int k = 0; k <= 8; ++k) {
    const double a = (first_deg + (last_deg - first_deg) * k / 8.0) * M_PI / 180.0;
    p.push_back(at + 10.0 * Vec2(std::cos(a), std::sin(a)));
  }
  return p;
}

TEST(Metrics, IntrusionOutsideEveryScannersAperture) {
  // The polygon [0.5, 1.5]^2 holds a quarter of cell (1, 1), which the obstacle covers. A
  // scanner at (3.5, 1.5) looking east (45 deg either side) has the cell's centre behind it; one
  // looking west has it ahead; a rig of both has it in view; without any it is undefined.
  TruthFrame truth;
  truth.obstacles = {Box(1.25, 1.25, 1.75, 1.75)};
  HandMap map({"FFFF",  //
               "FFFF",  //
               "FFFF",  //
               "FFFF"});
  const Polygon polygon = Box(0.5, 0.5, 1.5, 1.5);
  const Vec2 scanner(3.5, 1.5);
  truth.visible = Fan(scanner, -45, 45);
  ScanMetrics m = QualityEvaluator().Evaluate(map.view, polygon, truth);
  EXPECT_DOUBLE_EQ(m.intrusion_m2, 0.25);
  EXPECT_DOUBLE_EQ(m.intrusion_out_of_view_m2, 0.25);
  truth.visible = Fan(scanner, 135, 225);  // across the bearing 180 deg
  EXPECT_DOUBLE_EQ(QualityEvaluator().Evaluate(map.view, polygon, truth).intrusion_out_of_view_m2,
                   0.0);
  truth.visible = Fan(scanner, -45, 45);
  truth.visible_more = {Fan(scanner, 135, 225)};
  m = QualityEvaluator().Evaluate(map.view, polygon, truth);
  EXPECT_DOUBLE_EQ(m.intrusion_m2, 0.25);
  EXPECT_DOUBLE_EQ(m.intrusion_out_of_view_m2, 0.0);
  truth.visible.clear();
  truth.visible_more.clear();
  m = QualityEvaluator().Evaluate(map.view, polygon, truth);
  EXPECT_DOUBLE_EQ(m.intrusion_m2, 0.25);
  EXPECT_TRUE(std::isnan(m.intrusion_out_of_view_m2));
  EXPECT_TRUE(m.ToJson()["intrusion_out_of_view_m2"].is_null());
}

TEST(Metrics, TheSeenAreaAccumulatesAndMovesWithTheMap) {
  TruthFrame truth;
  truth.visible = Box(0, 0, 1, 4);  // column 0 of the first map (world x 0 .. 1)
  HandMap first({"FFFF", "FFFF", "FFFF", "FFFF"});
  QualityEvaluator evaluator;
  const std::vector<Vec2> polygon = Box(0, 0, 4, 4);
  EXPECT_DOUBLE_EQ(evaluator.Evaluate(first.view, polygon, truth).reference_seen_m2, 4.0);
  // The map moves one cell west: world x 0 .. 1 is now column 1. This scan sees nothing new.
  truth.visible.clear();
  HandMap west({"FFFF", "FFFF", "FFFF", "FFFF"}, {-1, 0});
  const ScanMetrics m = evaluator.Evaluate(west.view, polygon, truth);
  EXPECT_DOUBLE_EQ(m.reference_seen_m2, 4.0);
  EXPECT_EQ(evaluator.seen()[0 * 4 + 1], 1);
  EXPECT_EQ(evaluator.seen()[0 * 4 + 0], 0);
  // Two cells east: world x 0 .. 1 has left the map.
  HandMap east({"FFFF", "FFFF", "FFFF", "FFFF"}, {1, 0});
  EXPECT_TRUE(std::isnan(evaluator.Evaluate(east.view, polygon, truth).coverage_seen));
  // A map whose origin is not a whole number of cells away restarts the seen area.
  truth.visible = WholeMap();
  HandMap shifted({"FFFF", "FFFF", "FFFF", "FFFF"}, {0.5, 0});
  EXPECT_DOUBLE_EQ(evaluator.Evaluate(shifted.view, polygon, truth).reference_seen_m2, 16.0);
}

// A map whose axes are turned (MapView::map_yaw, as alignment rotate or scan_match leave them)
// is scored in its own cells: the hand case above, its map, truth and polygon all carried by one
// rigid motion, scores the same; with the map's yaw left out it would not.
TEST(Metrics, ARotatedMapIsScoredInItsOwnAxes) {
  TruthFrame truth;
  truth.obstacles = {Box(1.25, 1.25, 1.75, 1.75)};
  truth.visible = Box(0, 0, 3, 4);
  truth.in_sight = WholeMap();
  HandMap map({"FFF.",  //
               "FFFF",  //
               "FOFF",  //
               "FFFF"});
  const Polygon polygon = Box(0.5, 0.5, 2.5, 2.5);
  const Vec2 centre(0.5, 0.7);
  const ScanMetrics straight = QualityEvaluator().Evaluate(map.view, polygon, truth, centre);
  ASSERT_DOUBLE_EQ(straight.intrusion_m2, 1.0);

  // The map's cells laid in the world turned by `yaw` about `origin`, and everything with them.
  const auto place = [&](double yaw, const Vec2& origin, TruthFrame* t, HandMap* m) {
    const double c = std::cos(yaw), s = std::sin(yaw);
    const auto move = [&](const Polygon& p) {
      Polygon out;
      for (const Vec2& v : p)
        out.push_back(origin + Vec2(c * v.x() - s * v.y(), s * v.x() + c * v.y()));
      return out;
    };
    for (Polygon& o : t->obstacles) o = move(o);
    t->visible = move(t->visible);
    t->in_sight = move(t->in_sight);
    m->view.log_odds = m->log_odds.data();
    m->view.free = m->free.data();
    m->view.origin = origin;
    m->view.map_yaw = yaw;
    return move(polygon);
  };
  TruthFrame turned_truth = truth;
  HandMap turned = map;
  const Polygon turned_polygon = place(0.7, {3.0, -2.0}, &turned_truth, &turned);
  QualityEvaluator evaluator;
  const ScanMetrics m = evaluator.Evaluate(turned.view, turned_polygon, turned_truth, centre);
  EXPECT_NEAR(m.polygon_area_m2, straight.polygon_area_m2, 1e-9);
  EXPECT_NEAR(m.intrusion_m2, straight.intrusion_m2, 1e-9);
  EXPECT_NEAR(m.intrusion_geometric_m2, straight.intrusion_geometric_m2, 1e-9);
  EXPECT_EQ(m.correct, straight.correct);
  EXPECT_EQ(m.false_free, straight.false_free);
  EXPECT_NEAR(m.reference_free_m2, straight.reference_free_m2, 1e-9);
  EXPECT_NEAR(m.covered_free_m2, straight.covered_free_m2, 1e-9);
  EXPECT_NEAR(m.reference_star_m2, straight.reference_star_m2, 1e-9);
  EXPECT_NEAR(m.reference_seen_m2, straight.reference_seen_m2, 1e-9);

  // The next map turned further: the cells seen before are not carried into it. This scan sees
  // column 0 only (4 free cells); carried over, columns 1 and 2 would count too.
  TruthFrame next_truth = truth;
  next_truth.visible = Box(0, 0, 1, 4);
  HandMap next = map;
  const Polygon next_polygon = place(0.8, {3.0, -2.0}, &next_truth, &next);
  EXPECT_NEAR(evaluator.Evaluate(next.view, next_polygon, next_truth).reference_seen_m2, 4.0, 1e-9);
}

TEST(Metrics, SummaryPoolsAndAverages) {
  MetricsSeries series;
  ScanMetrics a, b;
  a.observed = 10;
  a.correct = 9;
  a.accuracy = 0.9;
  a.observed_occupied = 4;
  a.false_free = 2;
  a.false_free_rate = 0.5;
  a.intrusion_m2 = 1.0;
  a.coverage = std::nan("");
  b.observed = 30;
  b.correct = 30;
  b.accuracy = 1.0;
  b.observed_occupied = 0;
  b.false_free_rate = std::nan("");
  b.intrusion_m2 = 3.0;
  b.reference_free_m2 = 2.0;
  b.covered_free_m2 = 1.0;
  b.coverage = 0.5;
  series.Add(a);
  series.Add(b);
  const nlohmann::json s = series.Summary();
  EXPECT_DOUBLE_EQ(s["accuracy"]["mean"].get<double>(), 0.95);
  EXPECT_DOUBLE_EQ(s["accuracy"]["pooled"].get<double>(), 39.0 / 40.0);
  EXPECT_DOUBLE_EQ(s["false_free_rate"]["mean"].get<double>(), 0.5);  // b has none to score
  EXPECT_DOUBLE_EQ(s["false_free_rate"]["pooled"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(s["intrusion_m2"]["mean"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(s["intrusion_m2"]["max"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(s["coverage"]["mean"].get<double>(), 0.5);
  EXPECT_TRUE(a.ToJson()["coverage"].is_null());
}

// Runs the estimator over `scans` and scores each against `truth`.
std::vector<ScanMetrics> Score(const sim::Truth& truth, const std::vector<Scan>& scans) {
  Config config;
  config.sensor = truth.scanner.EngineSensor();
  Estimator estimator(config);
  sim::TruthScorer scorer(truth);
  std::vector<ScanMetrics> out;
  for (const Scan& scan : scans) {
    const Result& r = estimator.Process(scan);
    out.push_back(scorer.Score(scorer.Find(r.timestamp_s), estimator.map(), r));
  }
  return out;
}

TEST(Metrics, ScoresFromTheWrittenLogAndTruthEqualTheDrivesOwn) {
  const std::string dir = ::testing::TempDir() + "/metrics_round_trip";
  std::filesystem::create_directories(dir);
  sim::SimulationOptions options;
  options.scenario = "parking";
  options.duration_s = 3.0;
  options.odometry = sim::OdometryNoise::Preset("typical");
  sim::Simulation simulation(options);
  sim::SimulationWriter writer(dir, simulation.truth());
  std::vector<Scan> scans;
  Scan scan;
  while (simulation.Next(&scan)) {
    writer.Write(scan, simulation.last());
    scans.push_back(scan);
  }
  writer.Close();
  const std::vector<ScanMetrics> live = Score(simulation.truth(), scans);

  auto reader = OpenLog(writer.log_path());
  std::vector<Scan> read;
  while (reader->Next(&scan)) read.push_back(scan);
  const std::vector<ScanMetrics> replayed = Score(sim::ReadTruth(writer.truth_path()), read);
  ASSERT_EQ(live.size(), replayed.size());
  for (std::size_t i = 0; i < live.size(); ++i) {
    EXPECT_EQ(live[i].ToJson(), replayed[i].ToJson()) << "scan " << i;
  }
  // Sane values on a real drive: a polygon, a mostly right map, mostly covered free space.
  const ScanMetrics& last = live.back();
  EXPECT_GT(last.polygon_area_m2, 50.0);
  EXPECT_GT(last.accuracy, 0.95);
  EXPECT_GT(last.coverage, 0.5);
  EXPECT_LE(last.coverage, 1.0);
}

}  // namespace
}  // namespace freespace
