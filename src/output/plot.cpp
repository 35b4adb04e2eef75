// Line plots with OpenCV: axes with decade (or linear) ticks, one polyline per series.
#include "output/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "output/render.hpp"

namespace freespace {

void WriteLinePlot(const std::string& path, const PlotSpec& spec,
                   const std::vector<PlotSeries>& series) {
  const int width = 900, height = 620, left = 90, right = 30, top = 70, bottom = 70;
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
  for (const PlotSeries& s : series) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!(s.y[i] > 0) && spec.log_y) continue;
      x_lo = std::min(x_lo, s.x[i]);
      x_hi = std::max(x_hi, s.x[i]);
      y_lo = std::min(y_lo, s.y[i]);
      y_hi = std::max(y_hi, s.y[i]);
    }
  }
  if (!(x_lo < x_hi)) x_hi = x_lo + 1;
  if (!(y_lo < y_hi)) y_hi = y_lo + 1;
  auto tx = [&](double v) { return spec.log_x ? std::log10(v) : v; };
  auto ty = [&](double v) { return spec.log_y ? std::log10(v) : v; };
  double ax0 = tx(x_lo), ax1 = tx(x_hi), ay0 = ty(y_lo), ay1 = ty(y_hi);
  const double pad_x = 0.05 * (ax1 - ax0), pad_y = 0.08 * (ay1 - ay0);
  ax0 -= pad_x, ax1 += pad_x, ay0 -= pad_y, ay1 += pad_y;
  auto px = [&](double v) {
    return int(left + (tx(v) - ax0) / (ax1 - ax0) * (width - left - right));
  };
  auto py = [&](double v) {
    return int(height - bottom - (ty(v) - ay0) / (ay1 - ay0) * (height - top - bottom));
  };
  const cv::Scalar ink(40, 40, 40), grid(220, 220, 220);
  cv::rectangle(image, cv::Point(left, top), cv::Point(width - right, height - bottom), ink, 1);
  // Ticks: decades on log axes, five steps on linear ones.
  auto ticks = [](double lo, double hi, bool log) {
    std::vector<double> out;
    if (log) {
      for (double e = std::floor(lo); e <= std::ceil(hi); e += 1.0) {
        for (const double m : {1.0, 2.0, 5.0}) {
          const double v = m * std::pow(10.0, e);
          if (std::log10(v) >= lo && std::log10(v) <= hi) out.push_back(v);
        }
      }
    } else {
      for (int k = 0; k <= 5; ++k) out.push_back(lo + (hi - lo) * k / 5.0);
    }
    return out;
  };
  char text[64];
  for (const double v : ticks(ax0, ax1, spec.log_x)) {
    const int x = px(v);
    cv::line(image, cv::Point(x, top), cv::Point(x, height - bottom), grid, 1);
    std::snprintf(text, sizeof text, "%g", v);
    cv::putText(image, text, cv::Point(x - 15, height - bottom + 20), cv::FONT_HERSHEY_SIMPLEX,
                0.45, ink, 1, cv::LINE_AA);
  }
  for (const double v : ticks(ay0, ay1, spec.log_y)) {
    const int y = py(v);
    cv::line(image, cv::Point(left, y), cv::Point(width - right, y), grid, 1);
    std::snprintf(text, sizeof text, "%g", v);
    cv::putText(image, text, cv::Point(8, y + 5), cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1,
                cv::LINE_AA);
  }
  cv::putText(image, spec.title, cv::Point(8, 28), cv::FONT_HERSHEY_SIMPLEX, 0.7, ink, 2,
              cv::LINE_AA);
  cv::putText(image, spec.x_label, cv::Point(width / 2 - 80, height - 20), cv::FONT_HERSHEY_SIMPLEX,
              0.55, ink, 1, cv::LINE_AA);
  cv::putText(image, spec.y_label, cv::Point(8, top - 10), cv::FONT_HERSHEY_SIMPLEX, 0.5, ink, 1,
              cv::LINE_AA);
  const cv::Scalar colours[] = {{200, 80, 0},  {0, 120, 220}, {40, 160, 40},
                                {160, 0, 160}, {0, 0, 200},   {120, 120, 0}};
  for (std::size_t k = 0; k < series.size(); ++k) {
    const cv::Scalar colour = colours[k % 6];
    std::vector<cv::Point> points;
    for (std::size_t i = 0; i < series[k].x.size(); ++i) {
      if (spec.log_y && !(series[k].y[i] > 0)) continue;
      points.emplace_back(px(series[k].x[i]), py(series[k].y[i]));
    }
    if (points.size() > 1) cv::polylines(image, points, false, colour, 2, cv::LINE_AA);
    for (const cv::Point& p : points) cv::circle(image, p, 4, colour, -1, cv::LINE_AA);
    const int ly = top + 20 + int(k) * 22;
    cv::line(image, cv::Point(left + 15, ly - 5), cv::Point(left + 45, ly - 5), colour, 2);
    cv::putText(image, series[k].name, cv::Point(left + 52, ly), cv::FONT_HERSHEY_SIMPLEX, 0.5, ink,
                1, cv::LINE_AA);
  }
  WritePng(path, image);
}

}  // namespace freespace
