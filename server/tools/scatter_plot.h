// A scatter plot written as two files of the same drawing: SVG (plain text, scalable, points
// labelled on hover) and PNG (for viewers and documents that do not show SVG). What
// ddgi-shadow-eval and ddgi-eval draw error against GPU time, or per frame, with.
#pragma once

#include <string>
#include <vector>

#include "core/result.h"

namespace ddgi {

struct PlotPoint {
  double x = 0.0;
  double y = 0.0;
  std::string label;  // drawn beside the point
};

struct PlotSeries {
  std::string name;  // legend entry
  std::vector<PlotPoint> points;
  bool connected = false;  // a curve: a line through the points in x order (small markers)
};

struct ScatterPlot {
  std::string title;
  std::string x_label;
  std::string y_label;
  bool log_x = true;  // GPU times span orders of magnitude
  std::vector<PlotSeries> series;
};

// The plot as SVG text. Points with non-finite or (on a log axis) non-positive coordinates are
// left out.
std::string scatter_plot_svg(const ScatterPlot& plot);

// STEM.svg and STEM.png (plot_raster.h draws the PNG).
Status write_scatter_plot(const std::string& stem, const ScatterPlot& plot);

// A CSV field (RFC 4180) for the tables written beside plots: quoted when it holds a comma, a
// quote or a line break.
std::string csv_field(const std::string& text);

Status write_text_file(const std::string& path, const std::string& text);

}  // namespace ddgi
