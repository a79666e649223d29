// The plots' PNG side (server/tools/plot_raster.h): markers, lines and text land where the shared
// layout (and so the SVG) puts them, in the series' colours, and a missing font is refused by
// name. Measured values are stated beside each bound.
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "tools/plot_drawing.h"
#include "tools/plot_raster.h"
#include "tools/scatter_plot.h"

namespace ddgi {
namespace {

struct Rgb8 {
  int r, g, b;
};

Rgb8 pixel(const encode::ImageRgba8& image, int64_t x, int64_t y) {
  const uint8_t* p = &image.pixels[(size_t(y) * image.width + size_t(x)) * 4];
  return {p[0], p[1], p[2]};
}

bool near(Rgb8 a, PlotColour b, int tolerance) {
  return std::abs(a.r - b.r) <= tolerance && std::abs(a.g - b.g) <= tolerance &&
         std::abs(a.b - b.b) <= tolerance;
}

bool white(Rgb8 a) {
  return a.r == 255 && a.g == 255 && a.b == 255;
}

// The box around every pixel darker than mid-grey.
struct Ink {
  int64_t x0 = INT64_MAX, y0 = INT64_MAX, x1 = -1, y1 = -1, pixels = 0;
};

Ink ink_of(const encode::ImageRgba8& image) {
  Ink ink;
  for (int64_t y = 0; y < int64_t(image.height); ++y) {
    for (int64_t x = 0; x < int64_t(image.width); ++x) {
      if (pixel(image, x, y).r >= 128) continue;
      ink.x0 = std::min(ink.x0, x), ink.x1 = std::max(ink.x1, x);
      ink.y0 = std::min(ink.y0, y), ink.y1 = std::max(ink.y1, y);
      ++ink.pixels;
    }
  }
  return ink;
}

encode::ImageRgba8 draw_text(PlotText text) {
  PlotDrawing drawing{400, 400, {text}};
  Result<encode::ImageRgba8> image = rasterize_plot(drawing);
  EXPECT_TRUE(image.ok()) << image.error().message;
  return image.ok() ? *image : encode::ImageRgba8{};
}

TEST(PlotRaster, MarkersAndCurvesLandWhereTheLayoutPutsThemInTheSeriesColours) {
  ScatterPlot plot{"Title", "x label", "y label", false, {}};
  plot.series = {{"scattered", {{1, 1, "a"}, {2, 3, ""}, {4, 2, ""}}},
                 {"curve", {{1, 0.5, ""}, {4, 1.5, ""}}, true}};
  const PlotDrawing drawing = lay_out_scatter_plot(plot);
  Result<encode::ImageRgba8> image = scatter_plot_image(plot);
  ASSERT_TRUE(image.ok()) << image.error().message;
  EXPECT_EQ(image->width, drawing.width);
  EXPECT_EQ(image->height, drawing.height);

  // Every data marker's centre has its colour (the legend's too); the curve's segment midpoint
  // as well, and the SVG names the same centres.
  const std::string svg = scatter_plot_svg(plot);
  int markers = 0;
  for (const PlotItem& item : drawing.items) {
    const auto* disc = std::get_if<PlotDisc>(&item);
    if (disc == nullptr) continue;
    ++markers;
    EXPECT_TRUE(near(pixel(*image, int64_t(disc->x), int64_t(disc->y)), disc->colour, 40))
        << disc->tooltip << " at " << disc->x << "," << disc->y;
    std::ostringstream centre;
    centre << "cx=\"" << disc->x << "\" cy=\"" << disc->y << "\"";
    EXPECT_NE(svg.find(centre.str()), std::string::npos) << centre.str();
  }
  EXPECT_EQ(markers, 3 + 2 + 2);  // points and a legend marker per series
  int segments = 0;
  for (const PlotItem& item : drawing.items) {
    const auto* line = std::get_if<PlotLine>(&item);
    if (line == nullptr || line->width != 1.5) continue;
    ++segments;
    const Rgb8 mid = pixel(*image, std::lround((line->x0 + line->x1) / 2 - 0.5),
                           std::lround((line->y0 + line->y1) / 2 - 0.5));
    EXPECT_TRUE(near(mid, line->colour, 60)) << mid.r << "," << mid.g << "," << mid.b;
  }
  EXPECT_EQ(segments, 1);
  // Control: the corner is background, and the image is not one colour.
  EXPECT_TRUE(white(pixel(*image, 2, int64_t(image->height) - 3)));
  EXPECT_GT(ink_of(*image).pixels, 600);  // measured 988: tick labels, title, axis labels
}

TEST(PlotRaster, TextSitsOnItsAnchorAndReadsUpwardsWhenVertical) {
  const PlotColour black{0, 0, 0};
  // Start: ink begins at x (within the first glyph's bearing) and rests on the baseline.
  const Ink start = ink_of(draw_text({100, 200, "Hello 42", 32, TextAnchor::kStart, black}));
  EXPECT_NEAR(double(start.x0), 100.0, 4.0);  // measured 103
  EXPECT_NEAR(double(start.y1), 199.0, 1.0);  // measured 199: no descender in "Hello 42"
  EXPECT_GT(start.x1 - start.x0, 100);        // measured 125: eight glyphs of 32 px
  EXPECT_LT(start.y1 - start.y0, 30);         // cap height, measured 23
  // Middle and end: the same ink centred on x, ending at x.
  const Ink middle = ink_of(draw_text({200, 200, "Hello 42", 32, TextAnchor::kMiddle, black}));
  EXPECT_NEAR(double(middle.x0 + middle.x1) / 2, 200.0, 4.0);
  EXPECT_EQ(middle.x1 - middle.x0, start.x1 - start.x0);
  const Ink end = ink_of(draw_text({300, 200, "Hello 42", 32, TextAnchor::kEnd, black}));
  EXPECT_NEAR(double(end.x1), 300.0, 4.0);
  // Vertical: the same ink turned a quarter anticlockwise, above y and left of x.
  const Ink up = ink_of(draw_text({200, 300, "Hello 42", 32, TextAnchor::kStart, black, true}));
  EXPECT_EQ(up.y1 - up.y0, start.x1 - start.x0);
  EXPECT_EQ(up.x1 - up.x0, start.y1 - start.y0);
  EXPECT_LE(up.y1, 300 - 1);
  EXPECT_NEAR(double(up.y1), 300.0 - 4.0, 4.0);  // measured 296
  EXPECT_LE(up.x1, 200);
  // Different text, different ink (glyphs, not boxes): "1" has far less than "8".
  const Ink one = ink_of(draw_text({100, 100, "1", 32, TextAnchor::kStart, black}));
  const Ink eight = ink_of(draw_text({100, 100, "8", 32, TextAnchor::kStart, black}));
  EXPECT_LT(one.pixels * 3, eight.pixels * 2) << one.pixels << " vs " << eight.pixels;  // 113, 185
}

// Labels are UTF-8: a multi-byte letter is one glyph (ink of its own), a malformed byte one
// replacement glyph, never a read past the text.
TEST(PlotRaster, Utf8LabelsAreSetGlyphByGlyph) {
  const PlotColour black{0, 0, 0};
  const Ink plain = ink_of(draw_text({50, 100, "1.5 s", 32, TextAnchor::kStart, black}));
  const Ink micro = ink_of(draw_text({50, 100, "1.5 \u00b5s", 32, TextAnchor::kStart, black}));
  EXPECT_GT(micro.pixels, plain.pixels);
  EXPECT_GT(micro.x1 - micro.x0, plain.x1 - plain.x0 + 10);  // one more glyph, 32 px
  const Ink broken = ink_of(draw_text({50, 100, "a\xff", 32, TextAnchor::kStart, black}));
  const Ink a = ink_of(draw_text({50, 100, "a", 32, TextAnchor::kStart, black}));
  EXPECT_GT(broken.pixels, a.pixels);  // the replacement glyph drawn after "a"
}

TEST(PlotRaster, AMissingFontIsRefusedByName) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");  // a fresh process: the font is loaded once
  EXPECT_EXIT(
      {
        setenv("DDGI_PLOT_FONT", "/nonexistent/plot-font.ttf", 1);
        Result<encode::ImageRgba8> image = scatter_plot_image({});
        const bool named =
            !image.ok() &&
            image.error().message.find("/nonexistent/plot-font.ttf") != std::string::npos &&
            image.error().message.find("fonts-dejavu-core") != std::string::npos;
        if (!image.ok()) std::fprintf(stderr, "%s\n", image.error().message.c_str());
        std::exit(named ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "cannot read the plot font /nonexistent/plot-font.ttf");
}

}  // namespace
}  // namespace ddgi
