// The face layer: each face cut into pieces of at most one cell, every cell around a piece
// tested by its exact distance to the piece (cell units, the cell at (c, r) the unit square
// [c, c + 1] x [r, r + 1]).
#include "core/face_layer.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/fixed_point.hpp"
#include "core/preprocess.hpp"

namespace freespace {
namespace {

struct P {
  double x, y;
};

inline double Dist2PointCell(const P& p, int col, int row) {
  const double dx = std::max({col - p.x, 0.0, p.x - (col + 1)});
  const double dy = std::max({row - p.y, 0.0, p.y - (row + 1)});
  return dx * dx + dy * dy;
}

// A piece of a face, the segment a-b (a == b: a point), with what every cell's test of it
// shares worked out once, so that a test divides nothing.
class Piece {
 public:
  Piece(P a, P b)
      : a_(a),
        b_(b),
        dx_(b.x - a.x),
        dy_(b.y - a.y),
        inv_l2_(dx_ * dx_ + dy_ * dy_ > 0 ? 1.0 / (dx_ * dx_ + dy_ * dy_) : 0.0),
        lo_{std::min(a.x, b.x), std::min(a.y, b.y)},
        hi_{std::max(a.x, b.x), std::max(a.y, b.y)} {}

  // How the piece reaches the cell square [col, col + 1] x [row, row + 1]: kTouches when they
  // meet, kNear when it lies within sqrt(t2) of it (an end near the square, or a corner near
  // the piece), else kApart.
  enum Reach { kApart, kNear, kTouches };
  Reach ReachOf(int col, int row, double t2) const {
    if (inv_l2_ == 0.0) {
      const double d2 = Dist2PointCell(a_, col, row);
      return d2 == 0.0 ? kTouches : (d2 <= t2 ? kNear : kApart);
    }
    if (Meets(col, row)) return kTouches;
    if (Dist2PointCell(a_, col, row) <= t2 || Dist2PointCell(b_, col, row) <= t2) return kNear;
    for (int k = 0; k < 4; ++k) {
      if (Dist2Corner(col + (k & 1), row + (k >> 1)) <= t2) return kNear;
    }
    return kApart;
  }

 private:
  // Whether the piece meets the closed square: their boxes overlap, and the square's corners are
  // not all on one side of the piece's line (the axes that could part two convex shapes).
  bool Meets(int col, int row) const {
    if (hi_.x < col || lo_.x > col + 1 || hi_.y < row || lo_.y > row + 1) return false;
    const double f = dx_ * (row - a_.y) - dy_ * (col - a_.x);  // the side of corner (col, row)
    const double f_lo = f + std::min(0.0, dx_) + std::min(0.0, -dy_);
    const double f_hi = f + std::max(0.0, dx_) + std::max(0.0, -dy_);
    return f_lo <= 0.0 && f_hi >= 0.0;
  }
  double Dist2Corner(double x, double y) const {
    const double s = std::clamp(((x - a_.x) * dx_ + (y - a_.y) * dy_) * inv_l2_, 0.0, 1.0);
    const double ex = a_.x + s * dx_ - x, ey = a_.y + s * dy_ - y;
    return ex * ex + ey * ey;
  }

  P a_, b_;
  double dx_, dy_, inv_l2_;
  P lo_, hi_;  // the piece's box
};

// Where the cells go: the two lists, and the last cells found touched (near and seen already),
// whose tests the next pieces, which mostly share them, skip.
struct Sink {
  std::vector<std::int32_t>* near;
  std::vector<std::int32_t>* seen;
  std::int32_t recent[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
  unsigned next = 0;

  bool Touched(std::int32_t cell) const {
    bool found = false;
    for (const std::int32_t r : recent) found |= r == cell;
    return found;
  }
  void Add(std::int32_t cell, bool touched) {
    near->push_back(cell);
    if (!touched) return;
    seen->push_back(cell);
    recent[next++ % 8] = cell;
  }
};

// The cells within t of the segment a-b (a == b: of a point), into the sink's near list; those it
// touches, into its seen list.
inline void AddPiece(const P& a, const P& b, double t, int width, int height, Sink* sink) {
  const int c0 = std::max(0, FloorCell(std::min(a.x, b.x) - t));
  const int c1 = std::min(width - 1, FloorCell(std::max(a.x, b.x) + t));
  const int r0 = std::max(0, FloorCell(std::min(a.y, b.y) - t));
  const int r1 = std::min(height - 1, FloorCell(std::max(a.y, b.y) + t));
  const Piece piece(a, b);
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      const std::int32_t cell = r * width + c;
      if (sink->Touched(cell)) continue;
      const Piece::Reach reach = piece.ReachOf(c, r, t * t);
      if (reach != Piece::kApart) sink->Add(cell, reach == Piece::kTouches);
    }
  }
}

// The faces of edges [begin, end) of one outline (FaceCells()), into a sink.
class FaceWalker {
 public:
  FaceWalker(const std::vector<std::int32_t>& vertices, const std::vector<Beam>& beams,
             const FaceRule& rule, int width, int height)
      : vertices_(vertices),
        beams_(beams),
        rule_(rule),
        t_(rule.tolerance_m / rule.resolution_m),
        width_(width),
        height_(height) {}

  void Walk(std::size_t begin, std::size_t end, Sink* sink) const {
    const std::size_t n = beams_.size();
    std::size_t left = n, right = 0;  // the real beams around the edge; n: none
    for (std::size_t j = begin; j-- > 0;) {
      if (!beams_[j].is_virtual) {
        left = j;
        break;
      }
    }
    std::size_t last_point = n;  // the last beam added as a point
    for (std::size_t i = begin; i < end; ++i) {
      if (!beams_[i].is_virtual) left = i;
      if (right < i + 1) {
        right = i + 1;
        while (right < n && beams_[right].is_virtual) ++right;
      }
      const P a = At(i), b = At(i + 1);
      const double length = Distance(a, b);
      if (!IsFace(i, length, left, right)) {  // its real ends, each once
        if (!beams_[i].is_virtual && last_point != i) AddPoint(a, sink);
        if (!beams_[i + 1].is_virtual) AddPoint(b, sink);
        last_point = i + 1;
        continue;
      }
      const int whole = int(length);  // the ceiling of length >= 0, without a library call
      const int pieces = std::max(1, whole + (whole < length));
      if (pieces == 1) {  // the face itself, its ends as they are
        if (!Outside(a, b)) AddPiece(a, b, t_, width_, height_, sink);
        continue;
      }
      for (int k = 0; k < pieces; ++k) {
        const P u{a.x + (b.x - a.x) * k / pieces, a.y + (b.y - a.y) * k / pieces};
        const P v{a.x + (b.x - a.x) * (k + 1) / pieces, a.y + (b.y - a.y) * (k + 1) / pieces};
        if (!Outside(u, v)) AddPiece(u, v, t_, width_, height_, sink);
      }
    }
  }

 private:
  P At(std::size_t i) const {  // beam i's point, in cells
    return P{double(vertices_[2 * i + 2]) / kFixedOne, double(vertices_[2 * i + 3]) / kFixedOne};
  }
  static double Distance(P u, P v) {
    return std::sqrt((v.x - u.x) * (v.x - u.x) + (v.y - u.y) * (v.y - u.y));
  }
  bool Outside(P u, P v) const {
    return std::max(u.x, v.x) + t_ < 0 || std::min(u.x, v.x) - t_ > width_ ||
           std::max(u.y, v.y) + t_ < 0 || std::min(u.y, v.y) - t_ > height_;
  }
  void AddPoint(const P& a, Sink* sink) const {
    if (!Outside(a, a)) AddPiece(a, a, t_, width_, height_, sink);
  }
  // Whether `cells` between beams j and k is within the join distance.
  bool Within(std::size_t j, std::size_t k, double cells) const {
    const double join =
        rule_.join_m + rule_.join_per_m * std::min(beams_[j].range, beams_[k].range);
    return cells * rule_.resolution_m <= join;
  }
  // The edge from beam i to i + 1 (`length` cells; `left`, `right` the real beams around it) is a
  // face when it is no longer than the join distance and, where it meets virtual beams, their
  // run is a gap in a surface rather than open space: no wider than rule.max_gap_rad, or bounded
  // by real beams within the join distance, or this is its first edge from a real beam (the
  // surface's silhouette, continued by one beam). A wider run's virtual points stand at the
  // nearer neighbour's range, on nothing.
  bool IsFace(std::size_t i, double length, std::size_t left, std::size_t right) const {
    if (!Within(i, i + 1, length)) return false;
    if (!beams_[i].is_virtual || !beams_[i + 1].is_virtual) return true;
    const std::size_t n = beams_.size();
    const std::size_t first = left < n ? left + 1 : 0, last = right < n ? right - 1 : n - 1;
    if (beams_[last].angle - beams_[first].angle <= rule_.max_gap_rad) return true;
    return left < n && right < n && Within(left, right, Distance(At(left), At(right)));
  }

  const std::vector<std::int32_t>& vertices_;
  const std::vector<Beam>& beams_;
  const FaceRule& rule_;
  const double t_;
  const int width_, height_;
};

}  // namespace

FaceRule FaceRule::Of(const Config& config) {
  FaceRule rule;
  if (config.polygon.shape == PolygonShape::kInside)
    rule.tolerance_m = config.polygon.face_tolerance_m;
  rule.join_m = config.clutter.eps_m;
  rule.join_per_m = config.clutter.eps_per_m;
  rule.resolution_m = config.map.resolution_m;
  rule.max_gap_rad = kMaxGapDeg * M_PI / 180.0;
  return rule;
}

void FaceCells(const std::vector<std::int32_t>& vertices, const std::vector<Beam>& beams,
               const FaceRule& rule, int width, int height, std::vector<FaceLists>* parts,
               std::vector<std::int32_t>* near, std::vector<std::int32_t>* seen) {
  const std::size_t edges = beams.size() > 1 ? beams.size() - 1 : 0;
  const std::size_t count = parts->size();
  const FaceWalker walker(vertices, beams, rule, width, height);
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t k) {
    FaceLists& part = (*parts)[k];
    part.near.clear();
    part.seen.clear();
    Sink sink{&part.near, &part.seen};
    walker.Walk(edges * k / count, edges * (k + 1) / count, &sink);
  });
  for (const FaceLists& part : *parts) {
    near->insert(near->end(), part.near.begin(), part.near.end());
    seen->insert(seen->end(), part.seen.begin(), part.seen.end());
  }
}

}  // namespace freespace
