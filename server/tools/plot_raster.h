// The scatter plot as an image for its PNG file: the shared layout (tools/plot_drawing.h)
// rasterised with antialiased strokes and markers, text set with stb_truetype (the system libstb)
// in DejaVu Sans from Debian's fonts-dejavu-core. No OpenImageIO: the server's tools keep out of
// it (server/encode/CMakeLists.txt says why).
#pragma once

#include "core/result.h"
#include "encode/image.h"
#include "tools/plot_drawing.h"
#include "tools/scatter_plot.h"

namespace ddgi {

inline constexpr const char* kPlotFontFamily = "DejaVu Sans";  // what the SVG asks for too
// Where the font is read from unless the environment's DDGI_PLOT_FONT names another TrueType
// file (deploy/gpu-run.sh points it at the copy deploy/gpu-bundle.sh carries).
inline constexpr const char* kPlotFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

// FAILED_PRECONDITION naming the font file and its package when the font cannot be read.
Result<encode::ImageRgba8> rasterize_plot(const PlotDrawing& drawing);

Result<encode::ImageRgba8> scatter_plot_image(const ScatterPlot& plot);

}  // namespace ddgi
