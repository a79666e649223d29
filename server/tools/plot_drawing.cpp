// The scatter plot's layout (tools/plot_drawing.h): axes fitted to the points, ticks, labels,
// legend, markers and the lines of connected series, as primitives in pixels.
#include "tools/plot_drawing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ddgi {
namespace {

constexpr double kWidth = 800, kHeight = 520;
constexpr double kLeft = 80, kRight = 220, kTop = 50, kBottom = 60;  // margins (legend right)
constexpr PlotColour kSeriesColours[] = {{0x1f, 0x77, 0xb4}, {0xd6, 0x27, 0x28}, {0x2c, 0xa0, 0x2c},
                                         {0x94, 0x67, 0xbd}, {0xff, 0x7f, 0x0e}, {0x17, 0xbe, 0xcf},
                                         {0x8c, 0x56, 0x4b}, {0xe3, 0x77, 0xc2}};
constexpr PlotColour kInk{0x00, 0x00, 0x00}, kFrame{0x44, 0x44, 0x44}, kGrid{0xdd, 0xdd, 0xdd};

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.4g", v);
  return buffer;
}

// A round step (1, 2 or 5 times a power of ten) that cuts `range` into about `parts`.
double round_step(double range, double parts) {
  const double raw = range / parts, magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double mantissa = raw / magnitude;
  return (mantissa <= 1.0 ? 1.0 : mantissa <= 2.0 ? 2.0 : mantissa <= 5.0 ? 5.0 : 10.0) * magnitude;
}

// Data coordinates -> pixels. x is stored as log10(x) on a log axis.
struct Axes {
  bool log_x = true;
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  double y_step = 0.2;  // between y ticks; y0 and y1 are multiples of it
  double plot_width() const { return kWidth - kLeft - kRight; }
  double plot_height() const { return kHeight - kTop - kBottom; }
  bool usable(const PlotPoint& p) const {
    return std::isfinite(p.x) && std::isfinite(p.y) && (!log_x || p.x > 0.0);
  }
  double px(double x) const {
    return kLeft + ((log_x ? std::log10(x) : x) - x0) / (x1 - x0) * plot_width();
  }
  double py(double y) const { return kTop + plot_height() - (y - y0) / (y1 - y0) * plot_height(); }
};

Axes fit_axes(const ScatterPlot& plot) {
  Axes axes;
  axes.log_x = plot.log_x;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const PlotSeries& s : plot.series) {
    for (const PlotPoint& p : s.points) {
      if (!axes.usable(p)) continue;
      const double x = plot.log_x ? std::log10(p.x) : p.x;
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
      y0 = std::min(y0, p.y);
      y1 = std::max(y1, p.y);
    }
  }
  if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  const double xpad = std::max(0.05 * (x1 - x0), 0.05);
  axes.x0 = x0 - xpad;
  axes.x1 = x1 + xpad;
  // y from zero (errors are compared in proportion) to a round value above the largest.
  const double low = std::min(0.0, y0), high = y1 > low ? y1 + 0.02 * (y1 - low) : low + 1.0;
  axes.y_step = round_step(high - low, 5.0);
  axes.y0 = std::floor(low / axes.y_step) * axes.y_step;
  axes.y1 = std::ceil(high / axes.y_step) * axes.y_step;
  return axes;
}

// Decades (and 2, 5 within them) on a log axis, round steps of about a tenth otherwise.
std::vector<double> x_ticks(const Axes& axes) {
  std::vector<double> ticks;
  if (axes.log_x) {
    for (int e = int(std::floor(axes.x0)); e <= int(std::ceil(axes.x1)); ++e) {
      for (double m : {1.0, 2.0, 5.0}) {
        const double v = m * std::pow(10.0, e);
        if (std::log10(v) >= axes.x0 && std::log10(v) <= axes.x1) ticks.push_back(v);
      }
    }
  } else {
    const double step = round_step(axes.x1 - axes.x0, 10.0);
    for (double k = std::ceil(axes.x0 / step); k * step <= axes.x1; k += 1.0) {
      ticks.push_back(k * step);
    }
  }
  return ticks;
}

void draw_axes(const ScatterPlot& plot, const Axes& axes, PlotDrawing& d) {
  const double left = kLeft, right = kLeft + axes.plot_width();
  const double top = kTop, bottom = kTop + axes.plot_height();
  d.items.push_back(PlotText{kWidth / 2, 24, plot.title, 15, TextAnchor::kMiddle, kInk, false});
  for (double v : x_ticks(axes)) {
    d.items.push_back(PlotLine{axes.px(v), top, axes.px(v), bottom, 1.0, kGrid});
    d.items.push_back(PlotText{axes.px(v), bottom + 16, number(v), 12, TextAnchor::kMiddle, kInk});
  }
  const int y_ticks = int(std::lround((axes.y1 - axes.y0) / axes.y_step));
  for (int i = 0; i <= y_ticks; ++i) {
    const double v = axes.y0 + axes.y_step * i;
    d.items.push_back(PlotLine{left, axes.py(v), right, axes.py(v), 1.0, kGrid});
    d.items.push_back(PlotText{left - 6, axes.py(v) + 4, number(v), 12, TextAnchor::kEnd, kInk});
  }
  for (const PlotLine& edge : {PlotLine{left, top, right, top, 1.0, kFrame},
                               PlotLine{right, top, right, bottom, 1.0, kFrame},
                               PlotLine{right, bottom, left, bottom, 1.0, kFrame},
                               PlotLine{left, bottom, left, top, 1.0, kFrame}}) {
    d.items.push_back(edge);
  }
  d.items.push_back(
      PlotText{left + axes.plot_width() / 2, kHeight - 18, plot.x_label, 12, TextAnchor::kMiddle});
  d.items.push_back(PlotText{20, top + axes.plot_height() / 2, plot.y_label, 12,
                             TextAnchor::kMiddle, kInk, true});
}

void draw_series(const PlotSeries& series, size_t index, const Axes& axes, PlotDrawing& d) {
  const PlotColour colour = kSeriesColours[index % std::size(kSeriesColours)];
  const double legend_x = kLeft + axes.plot_width() + 18, legend_y = kTop + 10 + 18.0 * index;
  d.items.push_back(PlotDisc{legend_x, legend_y, 4, colour, ""});
  d.items.push_back(PlotText{legend_x + 10, legend_y + 4, series.name, 12, TextAnchor::kStart});
  // A connected series is a curve: a line through its points in x order, small markers.
  std::vector<PlotPoint> points;
  for (const PlotPoint& p : series.points) {
    if (axes.usable(p)) points.push_back(p);
  }
  const double radius = series.connected ? 2.0 : 4.0;
  if (series.connected) {
    std::stable_sort(points.begin(), points.end(),
                     [](const PlotPoint& a, const PlotPoint& b) { return a.x < b.x; });
    for (size_t i = 1; i < points.size(); ++i) {
      const PlotPoint &a = points[i - 1], &b = points[i];
      d.items.push_back(
          PlotLine{axes.px(a.x), axes.py(a.y), axes.px(b.x), axes.py(b.y), 1.5, colour});
    }
  }
  for (const PlotPoint& p : points) {
    const double x = axes.px(p.x), y = axes.py(p.y);
    d.items.push_back(PlotDisc{x, y, radius, colour, series.name + ": " + p.label});
    if (!p.label.empty()) {
      d.items.push_back(PlotText{x + 6, y - 5, p.label, 9, TextAnchor::kStart, colour});
    }
  }
}

}  // namespace

PlotDrawing lay_out_scatter_plot(const ScatterPlot& plot) {
  PlotDrawing drawing;
  drawing.width = uint32_t(kWidth);
  drawing.height = uint32_t(kHeight);
  const Axes axes = fit_axes(plot);
  draw_axes(plot, axes, drawing);
  for (size_t s = 0; s < plot.series.size(); ++s) draw_series(plot.series[s], s, axes, drawing);
  return drawing;
}

}  // namespace ddgi
