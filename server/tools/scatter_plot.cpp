// Scatter plots as SVG from the shared layout (tools/plot_drawing.h), and the two files written.
#include "tools/scatter_plot.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "encode/write_image.h"
#include "tools/plot_drawing.h"
#include "tools/plot_raster.h"

namespace ddgi {
namespace {

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

std::string hex(PlotColour c) {
  char buffer[8];
  std::snprintf(buffer, sizeof(buffer), "#%02x%02x%02x", c.r, c.g, c.b);
  return buffer;
}

const char* anchor_name(TextAnchor anchor) {
  switch (anchor) {
    case TextAnchor::kStart:
      return "start";
    case TextAnchor::kMiddle:
      return "middle";
    case TextAnchor::kEnd:
      return "end";
  }
  return "start";
}

void write_item(std::ostringstream& svg, const PlotLine& l) {
  svg << "<line x1=\"" << l.x0 << "\" y1=\"" << l.y0 << "\" x2=\"" << l.x1 << "\" y2=\"" << l.y1
      << "\" stroke=\"" << hex(l.colour) << "\" stroke-width=\"" << l.width << "\"/>\n";
}

void write_item(std::ostringstream& svg, const PlotDisc& d) {
  svg << "<circle cx=\"" << d.x << "\" cy=\"" << d.y << "\" r=\"" << d.radius << "\" fill=\""
      << hex(d.colour) << "\">";
  if (!d.tooltip.empty()) svg << "<title>" << escape(d.tooltip) << "</title>";
  svg << "</circle>\n";
}

void write_item(std::ostringstream& svg, const PlotText& t) {
  svg << "<text x=\"" << t.x << "\" y=\"" << t.y << "\"";
  if (t.vertical) {
    svg << " transform=\"rotate(-90 " << t.x << " " << t.y << ")\"";
  }
  svg << " text-anchor=\"" << anchor_name(t.anchor) << "\" font-size=\"" << t.size << "\" fill=\""
      << hex(t.colour) << "\">" << escape(t.text) << "</text>\n";
}

std::string drawing_svg(const PlotDrawing& drawing) {
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << drawing.width << "\" height=\""
      << drawing.height << "\" font-family=\"" << kPlotFontFamily << ", sans-serif\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (const PlotItem& item : drawing.items) {
    std::visit([&](const auto& primitive) { write_item(svg, primitive); }, item);
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace

std::string scatter_plot_svg(const ScatterPlot& plot) {
  return drawing_svg(lay_out_scatter_plot(plot));
}

Status write_scatter_plot(const std::string& stem, const ScatterPlot& plot) {
  const PlotDrawing drawing = lay_out_scatter_plot(plot);  // one layout for both files
  DDGI_TRY(write_text_file(stem + ".svg", drawing_svg(drawing)));
  DDGI_ASSIGN_OR_RETURN(const encode::ImageRgba8 image, rasterize_plot(drawing));
  return encode::write_image(stem + ".png", image);
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
