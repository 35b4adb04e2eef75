// The conservative free-space polygon (polygon.shape inside): the border rays cast exactly
// from the sensor on the free mask, simplified, then pulled toward the sensor.
#include "core/inside_polygon.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/backend.hpp"

namespace freespace {

// The conservative polygon. Why it covers free cells only: each ray is free up to its vertex,
// so a cell that is not free can meet a fan triangle (sensor, a, b) of the result only away
// from its two rays; in the triangle's barycentric coordinates (alpha along a, beta along b)
// the least alpha + beta over such a cell's part inside the wedge is the largest factor by
// which a and b may be scaled toward the sensor without touching it. Moving a vertex toward
// the sensor along its ray only shrinks the triangles on both sides of it, so each vertex
// takes the smaller factor of its two edges and every triangle stays inside its free one.
namespace {

double Cross(const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); }

// Below this area (cells^2) a triangle or an overlap counts as none: rounding only.
constexpr double kAreaTolerance = 1e-9;

}  // namespace

InsidePolygonBuilder::InsidePolygonBuilder(int width, int height, int max_vertices, double epsilon,
                                           int threads)
    : width_(width),
      height_(height),
      simplifier_(max_vertices, epsilon),
      block_sat_(std::size_t((width + kBlock - 1) / kBlock + 1) *
                 ((height + kBlock - 1) / kBlock + 1)),
      block_row_(std::size_t((width + kBlock - 1) / kBlock)),
      arena_(threads > 0 ? threads : tbb::task_arena::automatic) {
  ring_.reserve(std::size_t(BorderLabelCount(height, width)));
  kept_.reserve(std::size_t(std::max(max_vertices, 3)) + 1);
  scale_.reserve(std::size_t(std::max(max_vertices, 3)) + 1);
  // The rays' targets: the border cells' centres in label order; the corner cells, which two
  // labels share, once.
  const int labels = BorderLabelCount(height, width);
  const CellIndex first = BorderCell(0, height, width);
  CellIndex last{-1, -1};
  for (int l = 0; l < labels; ++l) {
    const CellIndex cell = BorderCell(l, height, width);
    if ((cell.row == last.row && cell.col == last.col) ||
        (l > 0 && cell.row == first.row && cell.col == first.col)) {
      continue;
    }
    last = cell;
    targets_.emplace_back(cell.col + 0.5, cell.row + 0.5);
  }
}

double InsidePolygonBuilder::Trace(const std::uint8_t* free, const Vec2& sensor,
                                   const Vec2& target) const {
  const auto is_free = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < width_ && y < height_ && free[std::size_t(y) * width_ + x];
  };
  const Vec2 d = target - sensor;
  int cx = int(std::floor(sensor.x())), cy = int(std::floor(sensor.y()));
  const int sx = d.x() > 0 ? 1 : (d.x() < 0 ? -1 : 0);
  const int sy = d.y() > 0 ? 1 : (d.y() < 0 ? -1 : 0);
  // Amanatides-Woo: t of the next column / row border crossed, and the t per cell.
  double tx = sx > 0 ? (cx + 1 - sensor.x()) / d.x() : sx < 0 ? (cx - sensor.x()) / d.x() : 2.0;
  double ty = sy > 0 ? (cy + 1 - sensor.y()) / d.y() : sy < 0 ? (cy - sensor.y()) / d.y() : 2.0;
  const double dtx = sx != 0 ? 1.0 / std::abs(d.x()) : 0.0;
  const double dty = sy != 0 ? 1.0 / std::abs(d.y()) : 0.0;
  while (true) {
    const double t = std::min(tx, ty);
    if (t >= 1.0) return 1.0;
    if (tx == ty) {
      // Through a corner: the ray touches all three cells beyond it.
      if (!is_free(cx + sx, cy) || !is_free(cx, cy + sy) || !is_free(cx + sx, cy + sy)) return t;
      cx += sx;
      cy += sy;
      tx += dtx;
      ty += dty;
    } else if (tx < ty) {
      cx += sx;
      if (!is_free(cx, cy)) return t;
      tx += dtx;
    } else {
      cy += sy;
      if (!is_free(cx, cy)) return t;
      ty += dty;
    }
  }
}

namespace {

// A convex polygon in (alpha, beta) coordinates, at most 8 vertices (a square cut by three
// half-planes).
struct Clip {
  double v[8][2];
  int n = 0;
  // Keeps the part where c0 + c1 * alpha + c2 * beta >= 0 (Sutherland-Hodgman).
  void Cut(double c0, double c1, double c2) {
    double out[8][2];
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const double* p = v[i];
      const double* q = v[(i + 1) % n];
      const double fp = c0 + c1 * p[0] + c2 * p[1], fq = c0 + c1 * q[0] + c2 * q[1];
      if (fp >= 0) {
        out[m][0] = p[0];
        out[m][1] = p[1];
        ++m;
      }
      if ((fp >= 0) != (fq >= 0)) {
        const double f = fp / (fp - fq);
        out[m][0] = p[0] + f * (q[0] - p[0]);
        out[m][1] = p[1] + f * (q[1] - p[1]);
        ++m;
      }
    }
    n = m;
    for (int i = 0; i < n; ++i) {
      v[i][0] = out[i][0];
      v[i][1] = out[i][1];
    }
  }
  double Area() const {
    double a = 0.0;
    for (int i = 0; i < n; ++i) {
      a += v[i][0] * v[(i + 1) % n][1] - v[i][1] * v[(i + 1) % n][0];
    }
    return 0.5 * std::abs(a);
  }
};

}  // namespace

void InsidePolygonBuilder::EdgePull(const std::uint8_t* free, const Vec2& sensor, const Vec2& a,
                                    const Vec2& b, double* scale_a, double* scale_b) const {
  const Vec2 u = a - sensor, v = b - sensor;
  const double det = Cross(u, v);  // twice the triangle's area
  if (det < -kAreaTolerance) {     // turns clockwise: the sensor is not inside
    *scale_a = *scale_b = 0.0;
    return;
  }
  *scale_a = *scale_b = 1.0;
  if (det <= kAreaTolerance) return;  // no area: the edge runs along its traced rays
  // Three ways out, each the largest safe choice of its kind: both ends scaled alike
  // (least alpha + beta), only b moved (least beta / (1 - alpha) where alpha < 1: a not-free
  // point must stay beyond the chord a -> s b), or only a moved.
  double both = 1.0, only_b = 1.0, only_a = 1.0;
  const Vec2 tri[3] = {sensor, a, b};
  const double y0 = std::min({sensor.y(), a.y(), b.y()});
  const double y1 = std::max({sensor.y(), a.y(), b.y()});
  const int r0 = std::max(0, int(std::floor(y0))), r1 = std::min(height_ - 1, int(std::floor(y1)));
  // The not-free cells of row r, columns c0 .. c1, that overlap the triangle limit the ways out.
  const auto scan_row = [&](int r, int c0, int c1) {
    const std::uint8_t* row = free + std::size_t(r) * width_;
    for (int c = c0; c <= c1; ++c) {
      // Skip free cells a machine word at a time.
      const void* hit = std::memchr(row + c, 0, std::size_t(c1 - c + 1));
      if (hit == nullptr) break;
      c = int(static_cast<const std::uint8_t*>(hit) - row);
      // The cell's corners in (alpha, beta): p = sensor + alpha u + beta v.
      Clip cell;
      double least = INFINITY;
      for (const Vec2& corner : {Vec2(c, r), Vec2(c + 1, r), Vec2(c + 1, r + 1), Vec2(c, r + 1)}) {
        const Vec2 w = corner - sensor;
        double* ab = cell.v[cell.n++];
        ab[0] = Cross(w, v) / det;
        ab[1] = Cross(u, w) / det;
        least = std::min(least, ab[0] + ab[1]);
      }
      if (least >= 1.0) continue;  // wholly beyond the chord: no way out is limited by it
      cell.Cut(0, 1, 0);           // alpha >= 0
      cell.Cut(0, 0, 1);           // beta >= 0
      // The overlap's area in cells^2 is det times its area in (alpha, beta).
      if (cell.n < 3 || cell.Area() * det <= kAreaTolerance) continue;
      for (int i = 0; i < cell.n; ++i) both = std::min(both, cell.v[i][0] + cell.v[i][1]);
      Clip near_a = cell;    // alpha <= 1: beta / (1 - alpha) is constant along edges ending at
      near_a.Cut(1, -1, 0);  // alpha = 1, so the least lies at a vertex with alpha < 1
      for (int i = 0; i < near_a.n; ++i) {
        if (near_a.v[i][0] < 1.0) {
          only_b = std::min(only_b, near_a.v[i][1] / (1.0 - near_a.v[i][0]));
        }
      }
      Clip near_b = cell;
      near_b.Cut(1, 0, -1);
      for (int i = 0; i < near_b.n; ++i) {
        if (near_b.v[i][1] < 1.0) {
          only_a = std::min(only_a, near_b.v[i][0] / (1.0 - near_b.v[i][1]));
        }
      }
    }
  };
  // Bands of rows, halved until they are one row, and dropped as soon as the blocks under the
  // triangle's part in them are all free (thin triangles along free rays are dropped whole).
  int bands[64][2];
  int top = 0;
  bands[top][0] = r0;
  bands[top][1] = r1;
  ++top;
  while (top > 0) {
    --top;
    const int ra = bands[top][0], rb = bands[top][1];
    // The triangle's x extent within the band [ra, rb + 1].
    double x0 = INFINITY, x1 = -INFINITY;
    for (int i = 0; i < 3; ++i) {
      const Vec2& p = tri[i];
      const Vec2& q = tri[(i + 1) % 3];
      if (p.y() >= ra && p.y() <= rb + 1) {
        x0 = std::min(x0, p.x());
        x1 = std::max(x1, p.x());
      }
      for (const double y : {double(ra), double(rb + 1)}) {
        if ((p.y() - y) * (q.y() - y) < 0) {
          const double x = p.x() + (q.x() - p.x()) * (y - p.y()) / (q.y() - p.y());
          x0 = std::min(x0, x);
          x1 = std::max(x1, x);
        }
      }
    }
    if (x0 > x1) continue;
    const int c0 = std::max(0, int(std::floor(x0))), c1 = std::min(width_ - 1, int(std::floor(x1)));
    if (c0 > c1 || !BlocksNotFree(ra, rb, c0, c1)) continue;
    if (ra < rb) {
      const int mid = ra + (rb - ra) / 2;
      bands[top][0] = mid + 1;
      bands[top][1] = rb;
      bands[top + 1][0] = ra;
      bands[top + 1][1] = mid;
      top += 2;
      continue;
    }
    scan_row(ra, c0, c1);
  }
  both = std::clamp(both, 0.0, 1.0);
  only_a = std::clamp(only_a, 0.0, 1.0);
  only_b = std::clamp(only_b, 0.0, 1.0);
  // The choice that keeps the most of the triangle (its area scales with scale_a * scale_b).
  *scale_a = *scale_b = both;
  if (only_b > both * both && only_b >= only_a) {
    *scale_a = 1.0;
    *scale_b = only_b;
  } else if (only_a > both * both) {
    *scale_a = only_a;
    *scale_b = 1.0;
  }
}

void InsidePolygonBuilder::CountBlocks(const std::uint8_t* free) {
  const int bw = (width_ + kBlock - 1) / kBlock, bh = (height_ + kBlock - 1) / kBlock;
  std::uint32_t* sat = block_sat_.data();
  std::fill(sat, sat + bw + 1, 0u);
  for (int br = 0; br < bh; ++br) {
    std::fill(block_row_.begin(), block_row_.end(), std::uint8_t{0});
    for (int r = br * kBlock; r < std::min(height_, (br + 1) * kBlock); ++r) {
      const std::uint8_t* row = free + std::size_t(r) * width_;
      for (int bc = 0; bc < bw; ++bc) {
        const int c0 = bc * kBlock, c1 = std::min(width_, c0 + kBlock);
        if (c1 - c0 == 8) {
          std::uint64_t x;
          std::memcpy(&x, row + c0, 8);
          // A zero byte among the eight (the classic has-zero-byte test).
          block_row_[bc] |= ((x - 0x0101010101010101ull) & ~x & 0x8080808080808080ull) != 0;
        } else {
          for (int c = c0; c < c1; ++c) block_row_[bc] |= row[c] == 0;
        }
      }
    }
    // Summed-area table of not-free blocks: sat[(br + 1) * (bw + 1) + bc + 1] counts the
    // blocks in rows 0 .. br and columns 0 .. bc.
    std::uint32_t* above = sat + std::size_t(br) * (bw + 1);
    std::uint32_t* here = above + (bw + 1);
    here[0] = 0;
    std::uint32_t run = 0;
    for (int bc = 0; bc < bw; ++bc) {
      run += block_row_[bc];
      here[bc + 1] = above[bc + 1] + run;
    }
  }
}

bool InsidePolygonBuilder::BlocksNotFree(int r0, int r1, int c0, int c1) const {
  const int bw = (width_ + kBlock - 1) / kBlock;
  const int br0 = r0 / kBlock, br1 = r1 / kBlock + 1, bc0 = c0 / kBlock, bc1 = c1 / kBlock + 1;
  const std::uint32_t* sat = block_sat_.data();
  const std::size_t stride = std::size_t(bw) + 1;
  return sat[br1 * stride + bc1] - sat[br0 * stride + bc1] - sat[br1 * stride + bc0] +
             sat[br0 * stride + bc0] !=
         0;
}

double InsidePolygonBuilder::Build(const std::uint8_t* free, const Vec2& sensor,
                                   std::vector<Vec2>* polygon) {
  polygon->clear();
  ring_.clear();
  const int sx = int(std::floor(sensor.x())), sy = int(std::floor(sensor.y()));
  if (sx < 0 || sy < 0 || sx >= width_ || sy >= height_ || !free[std::size_t(sy) * width_ + sx]) {
    polygon->assign(3, sensor);
    return 0.0;
  }
  CountBlocks(free);
  // One ray per border cell, in label order (counter-clockwise; targets_), in parallel.
  const int rays = int(targets_.size());
  ring_.resize(targets_.size());
  arena_.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, rays, 64),
                      [&](const tbb::blocked_range<int>& range) {
                        for (int i = range.begin(); i != range.end(); ++i) {
                          const Vec2& target = targets_[i];
                          ring_[i] = sensor + Trace(free, sensor, target) * (target - sensor);
                        }
                      });
  });
  // Neighbouring rays can pass a not-free cell between them (a ray through a gap in a wall
  // next to one stopped by the wall): pull the ring in first, so that the simplification
  // works on a ring that already covers free cells only and has no such spikes.
  const int m = int(ring_.size());
  for (int k = 0; k < m; ++k) {
    Vec2& a = ring_[k];
    Vec2& b = ring_[(k + 1) % m];
    double sa = 1.0, sb = 1.0;
    EdgePull(free, sensor, a, b, &sa, &sb);
    a = sensor + sa * (a - sensor);
    b = sensor + sb * (b - sensor);
  }
  const double error = simplifier_.Simplify(ring_, sensor, &kept_);
  const int n = int(kept_.size());
  scale_.assign(std::size_t(n), 1.0);
  for (int k = 0; k < n; ++k) {
    const int next = (k + 1) % n;
    double sa = 1.0, sb = 1.0;
    EdgePull(free, sensor, ring_[kept_[k]], ring_[kept_[next]], &sa, &sb);
    scale_[k] = std::min(scale_[k], sa);
    scale_[next] = std::min(scale_[next], sb);
  }
  for (int k = 0; k < n; ++k) polygon->push_back(sensor + scale_[k] * (ring_[kept_[k]] - sensor));
  return error;
}

}  // namespace freespace
