// Scatter plots as SVG (tools/scatter_plot.h).
#include "tools/scatter_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace ddgi {
namespace {

constexpr double kWidth = 800, kHeight = 520;
constexpr double kLeft = 80, kRight = 220, kTop = 50, kBottom = 60;  // margins (legend right)
const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                "#ff7f0e", "#17becf", "#8c564b", "#e377c2"};

std::string escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<') {
      out += "&lt;";
    } else if (c == '>') {
      out += "&gt;";
    } else if (c == '&') {
      out += "&amp;";
    } else {
      out += c;
    }
  }
  return out;
}

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.4g", v);
  return buffer;
}

}  // namespace

std::string scatter_plot_svg(const ScatterPlot& plot) {
  auto usable = [&](const PlotPoint& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && (!plot.log_x || p.x > 0.0);
  };
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const PlotSeries& s : plot.series) {
    for (const PlotPoint& p : s.points) {
      if (!usable(p)) continue;
      const double x = plot.log_x ? std::log10(p.x) : p.x;
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
      y0 = std::min(y0, p.y);
      y1 = std::max(y1, p.y);
    }
  }
  if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  // Breathing room, and a y axis from zero: errors are compared in proportion.
  const double xpad = std::max(0.05 * (x1 - x0), 0.05);
  x0 -= xpad;
  x1 += xpad;
  y0 = std::min(0.0, y0);
  y1 = y1 > y0 ? y1 * 1.08 : y0 + 1.0;
  const double pw = kWidth - kLeft - kRight, ph = kHeight - kTop - kBottom;
  auto px = [&](double x) {
    return kLeft + ((plot.log_x ? std::log10(x) : x) - x0) / (x1 - x0) * pw;
  };
  auto py = [&](double y) { return kTop + ph - (y - y0) / (y1 - y0) * ph; };

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << kWidth / 2 << "\" y=\"24\" text-anchor=\"middle\" font-size=\"15\">"
      << escape(plot.title) << "</text>\n"
      << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << pw << "\" height=\"" << ph
      << "\" fill=\"none\" stroke=\"#444\"/>\n";
  // Ticks: decades (and 2, 5 within them) on a log axis, tenths of the range otherwise.
  std::vector<double> xticks;
  if (plot.log_x) {
    for (int e = int(std::floor(x0)); e <= int(std::ceil(x1)); ++e) {
      for (double m : {1.0, 2.0, 5.0}) {
        const double v = m * std::pow(10.0, e);
        if (std::log10(v) >= x0 && std::log10(v) <= x1) xticks.push_back(v);
      }
    }
  } else {
    for (int i = 0; i <= 10; ++i) xticks.push_back(x0 + (x1 - x0) * i / 10.0);
  }
  for (double v : xticks) {
    svg << "<line x1=\"" << px(v) << "\" y1=\"" << kTop << "\" x2=\"" << px(v) << "\" y2=\""
        << kTop + ph << "\" stroke=\"#ddd\"/>\n"
        << "<text x=\"" << px(v) << "\" y=\"" << kTop + ph + 16 << "\" text-anchor=\"middle\">"
        << number(v) << "</text>\n";
  }
  for (int i = 0; i <= 5; ++i) {
    const double v = y0 + (y1 - y0) * i / 5.0;
    svg << "<line x1=\"" << kLeft << "\" y1=\"" << py(v) << "\" x2=\"" << kLeft + pw << "\" y2=\""
        << py(v) << "\" stroke=\"#ddd\"/>\n"
        << "<text x=\"" << kLeft - 6 << "\" y=\"" << py(v) + 4 << "\" text-anchor=\"end\">"
        << number(v) << "</text>\n";
  }
  svg << "<text x=\"" << kLeft + pw / 2 << "\" y=\"" << kHeight - 18 << "\" text-anchor=\"middle\">"
      << escape(plot.x_label) << "</text>\n"
      << "<text transform=\"translate(20," << kTop + ph / 2
      << ") rotate(-90)\" text-anchor=\"middle\">" << escape(plot.y_label) << "</text>\n";

  for (size_t s = 0; s < plot.series.size(); ++s) {
    const PlotSeries& series = plot.series[s];
    const char* colour = kColours[s % (sizeof(kColours) / sizeof(kColours[0]))];
    const double ly = kTop + 10 + 18.0 * double(s);
    svg << "<circle cx=\"" << kLeft + pw + 18 << "\" cy=\"" << ly << "\" r=\"4\" fill=\"" << colour
        << "\"/>\n<text x=\"" << kLeft + pw + 28 << "\" y=\"" << ly + 4 << "\">"
        << escape(series.name) << "</text>\n";
    for (const PlotPoint& p : series.points) {
      if (!usable(p)) continue;
      svg << "<circle cx=\"" << px(p.x) << "\" cy=\"" << py(p.y) << "\" r=\"4\" fill=\"" << colour
          << "\"><title>" << escape(series.name + ": " + p.label) << "</title></circle>\n";
      if (p.label.empty()) continue;
      svg << "<text x=\"" << px(p.x) + 6 << "\" y=\"" << py(p.y) - 5 << "\" font-size=\"9\" fill=\""
          << colour << "\">" << escape(p.label) << "</text>\n";
    }
  }
  svg << "</svg>\n";
  return svg.str();
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

Status write_text_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return invalid_argument("cannot open '" + path + "' for writing");
  out << text;
  out.close();
  if (!out) return internal_error("cannot write '" + path + "'");
  return ok_status();
}

}  // namespace ddgi
