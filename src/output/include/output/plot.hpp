// Line plots as PNG (OpenCV drawing), for the scaling results of `freespace bench`.
#pragma once

#include <string>
#include <vector>

namespace freespace {

struct PlotSeries {
  std::string name;
  std::vector<double> x;
  std::vector<double> y;
};

struct PlotSpec {
  std::string title;
  std::string x_label;
  std::string y_label;
  bool log_x = true;
  bool log_y = true;
};

// Draws the series (markers and lines, one colour each, a legend) and writes a PNG.
// Throws InputError when the file cannot be written.
void WriteLinePlot(const std::string& path, const PlotSpec& spec,
                   const std::vector<PlotSeries>& series);

}  // namespace freespace
