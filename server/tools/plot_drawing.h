// A scatter plot laid out once as drawing primitives in pixel coordinates: the one layout the SVG
// writer (scatter_plot.cpp) and the PNG rasteriser (plot_raster.cpp) both draw, so the two files
// a tool writes show the same plot.
#pragma once

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "tools/scatter_plot.h"

namespace ddgi {

struct PlotColour {
  uint8_t r = 0, g = 0, b = 0;
};

struct PlotLine {  // a straight stroke (grid lines, the frame, segments of a connected series)
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  double width = 1.0;
  PlotColour colour;
};

struct PlotDisc {  // a marker
  double x = 0.0, y = 0.0, radius = 4.0;
  PlotColour colour;
  std::string tooltip;  // SVG only: shown on hover
};

enum class TextAnchor { kStart, kMiddle, kEnd };

struct PlotText {
  double x = 0.0, y = 0.0;  // where the baseline meets the anchor
  std::string text;         // UTF-8
  double size = 12.0;       // em size in pixels
  TextAnchor anchor = TextAnchor::kStart;
  PlotColour colour;
  bool vertical = false;  // rotated a quarter turn anticlockwise about (x, y): reads upwards
};

using PlotItem = std::variant<PlotLine, PlotDisc, PlotText>;

struct PlotDrawing {
  uint32_t width = 0, height = 0;  // pixels; the background is white
  std::vector<PlotItem> items;     // in drawing order: later items cover earlier ones
};

PlotDrawing lay_out_scatter_plot(const ScatterPlot& plot);

}  // namespace ddgi
