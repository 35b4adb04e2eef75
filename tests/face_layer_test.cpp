// The per-scan face layer (polygon.face_tolerance_m): which cells lie near this scan's faces and
// which its outline touches, on hand-made outlines with known answers.
#include "core/face_layer.hpp"

#include <algorithm>
#include <random>
#include <set>

#include "core/fixed_point.hpp"
#include "core/preprocess.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

constexpr int kWidth = 30, kHeight = 30;

struct Outline {
  std::vector<std::int32_t> vertices = {0, 0};  // vertex 0: the sensor, at the map's corner
  std::vector<Beam> beams;

  // A beam's point at (x, y) cells, `range` metres from the sensor; the beams 0.25 deg apart
  // unless `angle_deg` says.
  void Add(double x, double y, double range, bool is_virtual = false, double angle_deg = -1) {
    vertices.push_back(std::int32_t(x * kFixedOne));
    vertices.push_back(std::int32_t(y * kFixedOne));
    Beam b;
    b.angle = float((angle_deg >= 0 ? angle_deg : 0.25 * double(beams.size())) * M_PI / 180.0);
    b.range = float(range);
    b.is_virtual = is_virtual;
    beams.push_back(b);
  }
};

FaceRule Rule() {
  FaceRule rule;
  rule.max_gap_rad = kMaxGapDeg * M_PI / 180.0;
  rule.tolerance_m = 0.05;  // a quarter of a cell
  rule.join_m = 0.5;        // an edge over 2.5 cells joins two surfaces
  rule.join_per_m = 0.0;
  rule.resolution_m = 0.2;
  return rule;
}

// FaceCells() of `o` in `parts` parts.
void Faces(const Outline& o, std::vector<std::int32_t>* near, std::vector<std::int32_t>* seen,
           int parts = 1, const FaceRule& rule = Rule()) {
  std::vector<FaceLists> lists(parts);
  FaceCells(o.vertices, o.beams, rule, kWidth, kHeight, &lists, near, seen);
}

struct Pt {
  double x, y;
};

double Orient(Pt a, Pt b, Pt c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

double PointToSegment(Pt p, Pt a, Pt b) {
  const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
  const double t = l2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / l2, 0.0, 1.0) : 0.0;
  return std::hypot(a.x + t * dx - p.x, a.y + t * dy - p.y);
}

// The distance between the segment a-b and the square [x0, x1] x [y0, y1]: 0 with an end in
// it or a side crossed, else the least distance between the segment and a side (an end of one
// to the other).
double SquareDistance(Pt a, Pt b, double x0, double y0, double x1, double y1) {
  const auto in = [&](Pt p) { return p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1; };
  if (in(a) || in(b)) return 0.0;
  const Pt corner[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  double d = INFINITY;
  for (int k = 0; k < 4; ++k) {
    const Pt c = corner[k], e = corner[(k + 1) % 4];
    if (Orient(a, b, c) * Orient(a, b, e) < 0 && Orient(c, e, a) * Orient(c, e, b) < 0) return 0;
    d = std::min({d, PointToSegment(a, c, e), PointToSegment(b, c, e), PointToSegment(c, a, b),
                  PointToSegment(e, a, b)});
  }
  return d;
}

std::set<std::pair<int, int>> Cells(const std::vector<std::int32_t>& list) {
  std::set<std::pair<int, int>> cells;
  for (const std::int32_t i : list) {
    EXPECT_GE(i, 0);
    EXPECT_LT(i, kWidth * kHeight);
    cells.insert({i % kWidth, i / kWidth});  // (col, row)
  }
  return cells;
}

TEST(FaceLayer, ACellIsNearAFaceWithinTheTolerance) {
  // A wall along y = 10.1 from x = 2.5 to 8.5, beams one cell apart: it touches row 10, and row
  // 9's top edge lies 0.1 cell from it, within the quarter cell; row 11 (0.9 away) does not.
  Outline o;
  for (int k = 0; k <= 6; ++k) o.Add(2.5 + k, 10.1, 3.0);
  std::vector<std::int32_t> near, seen;
  Faces(o, &near, &seen);
  std::set<std::pair<int, int>> want_seen, want_near;
  for (int c = 2; c <= 8; ++c) {
    want_seen.insert({c, 10});
    want_near.insert({c, 10});
    want_near.insert({c, 9});
  }
  EXPECT_EQ(Cells(seen), want_seen);
  EXPECT_EQ(Cells(near), want_near);
}

TEST(FaceLayer, AnEdgeJoiningTwoSurfacesCountsOnlyAtItsRealEnds) {
  // A near wall ending at (5.5, 5.5), then a jump of 10 cells to a far one from (15.5, 15.5): the
  // join between them is no face, its ends are. The far wall's last point is virtual (no echo),
  // and stands at the end of a join: nothing of it is near.
  Outline o;
  o.Add(3.5, 5.5, 1.3);
  o.Add(5.5, 5.5, 1.5);
  o.Add(15.5, 15.5, 4.4);
  o.Add(17.5, 15.5, 4.6);
  o.Add(27.5, 25.5, 7.4, /*is_virtual=*/true);
  std::vector<std::int32_t> near, seen;
  Faces(o, &near, &seen);
  const std::set<std::pair<int, int>> cells = Cells(near);
  for (int c = 3; c <= 5; ++c) EXPECT_TRUE(cells.count({c, 5})) << c;
  for (int c = 15; c <= 17; ++c) EXPECT_TRUE(cells.count({c, 15})) << c;
  for (int k = 7; k <= 13; ++k) EXPECT_FALSE(cells.count({k, k})) << "on the join, " << k;
  EXPECT_FALSE(cells.count({27, 25}));
  EXPECT_FALSE(cells.count({22, 20})) << "on the second join";
  EXPECT_EQ(Cells(seen).size(), 6u);  // the two walls' cells only
}

TEST(FaceLayer, AFewMissingEchoesOnOneSurfaceAreAFace) {
  // No echo on the second beam, its neighbours two cells apart on one wall: the virtual point
  // stands on the wall, and the edges through it are faces like any other.
  Outline o;
  o.Add(3.5, 5.5, 1.3);
  o.Add(4.5, 5.5, 1.3, /*is_virtual=*/true);
  o.Add(5.5, 5.5, 1.5);
  std::vector<std::int32_t> near, seen;
  Faces(o, &near, &seen);
  EXPECT_EQ(Cells(seen), (std::set<std::pair<int, int>>{{3, 5}, {4, 5}, {5, 5}}));
}

// Three beams without echo between echoes 17 cells apart, then two at the end of the scan.
Outline RunsOfVirtualBeams(double run_step_deg) {
  Outline o;
  o.Add(3.5, 5.5, 1.3, false, 10.0);
  for (int k = 1; k <= 3; ++k) o.Add(3.5 + k, 5.5, 1.3, true, 10.0 + run_step_deg * k);
  o.Add(20.5, 5.5, 4.1, false, 10.0 + run_step_deg * 4);
  for (int k = 1; k <= 2; ++k) o.Add(20.5 + k, 5.5, 4.1, true, 10.0 + run_step_deg * (4 + k));
  return o;
}

TEST(FaceLayer, AWideRunWithoutEchoesIsNoFace) {
  // Runs 10 deg apart (open space between two objects): their virtual points stand on nothing.
  // The real points count, and each one's first short edge into a run (its silhouette, one beam
  // on); the rest of the runs does not.
  const Outline o = RunsOfVirtualBeams(10.0);
  std::vector<std::int32_t> near, seen;
  Faces(o, &near, &seen);
  EXPECT_EQ(Cells(seen), (std::set<std::pair<int, int>>{{3, 5}, {4, 5}, {20, 5}, {21, 5}}));
  EXPECT_EQ(Cells(near), Cells(seen));
}

TEST(FaceLayer, ANarrowRunWithoutEchoesIsAGapInTheSurface) {
  // The same runs 0.5 deg apart, within the gap's 8 deg: each short edge along them is a face;
  // the long edge to the far echo is not.
  const Outline o = RunsOfVirtualBeams(0.5);
  std::vector<std::int32_t> near, seen;
  Faces(o, &near, &seen);
  EXPECT_EQ(Cells(seen), (std::set<std::pair<int, int>>{
                             {3, 5}, {4, 5}, {5, 5}, {6, 5}, {20, 5}, {21, 5}, {22, 5}}));
  EXPECT_FALSE(Cells(near).count({12, 5}));
}

TEST(FaceLayer, CellsOutsideTheMapAreLeftOut) {
  // A wall running from outside the map, across its corner and out again.
  Outline o;
  for (int k = -6; k <= 6; ++k) o.Add(-3.0 + 0.5 * k + 3, 0.25 * k + 1.0, 2.0);
  std::vector<std::int32_t> near, seen;
  Faces(o, &near, &seen);
  EXPECT_FALSE(seen.empty());
  Cells(near);  // every index inside the map
  Cells(seen);
}

TEST(FaceLayer, EveryCellWithinTheToleranceAndNoOther) {
  // Random faces (two echoes within the join distance) and points (two echoes beyond it), at
  // tolerances from none to over a cell, against every cell's distance worked out on its own:
  // near holds the cells within the tolerance, seen those the face or point touches (up to
  // 1e-7 cells either way: what lies exactly on the edge may go either way).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> at(-2.0, kWidth + 2.0), step(-3.0, 3.0);
  int checked_near = 0, checked_seen = 0;
  for (int trial = 0; trial < 400; ++trial) {
    FaceRule rule = Rule();
    rule.tolerance_m = std::vector<double>{0.0, 0.05, 0.1, 0.33}[trial % 4];
    const double t = rule.tolerance_m / rule.resolution_m;
    Outline o;
    const double ax = at(rng), ay = at(rng);
    double bx = ax + step(rng), by = ay + step(rng);
    if (trial % 5 == 0) by = ay;  // along a row, or a column, or from a cell corner
    if (trial % 5 == 1) bx = ax;
    const double snap = trial % 7 == 0 ? 1.0 : 0.0;
    const auto on = [&](double v) { return snap > 0 ? std::round(v) : v; };
    o.Add(on(ax), on(ay), 3.0);
    o.Add(on(bx), on(by), 3.0);
    const double px = double(o.vertices[2]) / kFixedOne, py = double(o.vertices[3]) / kFixedOne;
    const double qx = double(o.vertices[4]) / kFixedOne, qy = double(o.vertices[5]) / kFixedOne;
    const bool face = std::hypot(qx - px, qy - py) * rule.resolution_m <= rule.join_m;
    std::vector<std::int32_t> near, seen;
    Faces(o, &near, &seen, 1, rule);
    const std::set<std::pair<int, int>> got_near = Cells(near), got_seen = Cells(seen);
    for (int r = 0; r < kHeight; ++r) {
      for (int c = 0; c < kWidth; ++c) {
        const Pt p{px, py}, q{qx, qy};
        const auto distance = [&](double shrink) {
          const double x0 = c + shrink, y0 = r + shrink, x1 = c + 1 - shrink, y1 = r + 1 - shrink;
          return face ? SquareDistance(p, q, x0, y0, x1, y1)
                      : std::min(SquareDistance(p, p, x0, y0, x1, y1),
                                 SquareDistance(q, q, x0, y0, x1, y1));
        };
        const double d = distance(0.0);
        const std::string where = "trial " + std::to_string(trial) + " cell (" + std::to_string(c) +
                                  ", " + std::to_string(r) + ")";
        const bool in_near = got_near.count({c, r}), in_seen = got_seen.count({c, r});
        if (d < t - 1e-7) {
          EXPECT_TRUE(in_near) << where << " at " << d;
        }
        if (d > t + 1e-7) {
          EXPECT_FALSE(in_near) << where << " at " << d;
        }
        if (d > 1e-7) {
          EXPECT_FALSE(in_seen) << where << " at " << d;
        }
        if (distance(1e-7) == 0.0) {  // touched with some length or depth
          EXPECT_TRUE(in_seen) << where;
        }
        checked_near += in_near;
        checked_seen += in_seen;
      }
    }
  }
  EXPECT_GT(checked_near, 2000);
  EXPECT_GT(checked_seen, 500);
}

TEST(FaceLayer, InPartsTheSameCells) {
  // A long random outline (walls, jumps, runs without echo) worked whole and in 3 and 7 parts
  // in parallel: the same cells.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> step(-0.6, 0.6);
  Outline o;
  double x = 15, y = 15;
  for (int k = 0; k < 900; ++k) {
    x = std::clamp(x + step(rng) * (k % 37 == 0 ? 12 : 1), -3.0, 33.0);
    y = std::clamp(y + step(rng) * (k % 41 == 0 ? 12 : 1), -3.0, 33.0);
    o.Add(x, y, 0.2 * std::hypot(x, y), rng() % 5 == 0);
  }
  std::vector<std::int32_t> near, seen;
  Faces(o, &near, &seen);
  ASSERT_GT(Cells(near).size(), 100u);
  for (const int count : {3, 7}) {
    std::vector<std::int32_t> part_near, part_seen;
    Faces(o, &part_near, &part_seen, count);
    EXPECT_EQ(Cells(part_near), Cells(near)) << count << " parts";
    EXPECT_EQ(Cells(part_seen), Cells(seen)) << count << " parts";
  }
}

}  // namespace
}  // namespace freespace
