// Rasterising a plot drawing (tools/plot_raster.h): coverage-antialiased lines and discs, glyphs
// from stb_truetype composited upright or rotated a quarter turn.
#include "tools/plot_raster.h"

#include <stb_truetype.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>

#include "encode/file_io.h"

namespace ddgi {
namespace {

// The font file's bytes and stb's view of them (which points into the bytes: never moved).
struct Font {
  std::vector<uint8_t> bytes;
  stbtt_fontinfo info{};
};

// Loaded once per process; every plot after the first reuses it.
Result<const Font*> plot_font() {
  static const Result<std::unique_ptr<Font>> font = []() -> Result<std::unique_ptr<Font>> {
    const char* chosen = std::getenv("DDGI_PLOT_FONT");
    const std::string path = chosen != nullptr && *chosen != '\0' ? chosen : kPlotFontPath;
    const std::string missing = "cannot read the plot font " + path +
                                " (Debian package fonts-dejavu-core, or DDGI_PLOT_FONT=FILE.ttf)";
    auto loaded = std::make_unique<Font>();
    Result<std::vector<uint8_t>> bytes = encode::read_file(path);
    if (!bytes.ok()) return failed_precondition(missing + ": " + bytes.error().message);
    loaded->bytes = std::move(*bytes);
    const int offset = stbtt_GetFontOffsetForIndex(loaded->bytes.data(), 0);
    if (offset < 0 || !stbtt_InitFont(&loaded->info, loaded->bytes.data(), offset)) {
      return failed_precondition(missing + ": not a TrueType font");
    }
    return loaded;
  }();
  if (!font.ok()) return font.error();
  return font->get();
}

// UTF-8 -> code points; a malformed byte becomes U+FFFD.
std::vector<int> code_points(const std::string& text) {
  std::vector<int> out;
  for (size_t i = 0; i < text.size();) {
    const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned lead = byte(i);
    const size_t length = lead < 0x80         ? 1
                          : (lead >> 5) == 6  ? 2
                          : (lead >> 4) == 14 ? 3
                          : (lead >> 3) == 30 ? 4
                                              : 0;
    bool valid = length > 0 && i + length <= text.size();
    for (size_t k = 1; valid && k < length; ++k) valid = (byte(i + k) & 0xc0) == 0x80;
    if (!valid) {
      out.push_back(0xfffd);
      ++i;
      continue;
    }
    int cp = length == 1 ? int(lead) : int(lead & (0x7f >> length));
    for (size_t k = 1; k < length; ++k) cp = (cp << 6) | int(byte(i + k) & 0x3f);
    out.push_back(cp);
    i += length;
  }
  return out;
}

class Canvas {
 public:
  Canvas(uint32_t width, uint32_t height)
      : width_(width), height_(height), rgb_(size_t(width) * height * 3, 1.0f) {}

  // Covers pixel (x, y) with `colour` by `coverage` in [0, 1]; outside the canvas: nothing.
  void blend(int64_t x, int64_t y, PlotColour colour, double coverage) {
    if (x < 0 || y < 0 || x >= int64_t(width_) || y >= int64_t(height_) || coverage <= 0.0) return;
    const float a = float(std::min(coverage, 1.0));
    float* p = &rgb_[(size_t(y) * width_ + size_t(x)) * 3];
    const uint8_t channels[3] = {colour.r, colour.g, colour.b};
    for (int c = 0; c < 3; ++c) p[c] += (float(channels[c]) / 255.0f - p[c]) * a;
  }

  // Every pixel whose centre lies within `reach` of the box, with the coverage `shade` gives it.
  template <typename Shade>
  void shade_box(double x0, double y0, double x1, double y1, double reach, Shade shade) {
    for (int64_t y = int64_t(std::floor(y0 - reach)); y <= int64_t(std::ceil(y1 + reach)); ++y) {
      for (int64_t x = int64_t(std::floor(x0 - reach)); x <= int64_t(std::ceil(x1 + reach)); ++x) {
        const auto [colour, coverage] = shade(double(x) + 0.5, double(y) + 0.5);
        blend(x, y, colour, coverage);
      }
    }
  }

  encode::ImageRgba8 image() const {
    encode::ImageRgba8 out{width_, height_, std::vector<uint8_t>(size_t(width_) * height_ * 4)};
    for (size_t i = 0; i < size_t(width_) * height_; ++i) {
      for (int c = 0; c < 3; ++c)
        out.pixels[i * 4 + c] = uint8_t(std::lround(rgb_[i * 3 + c] * 255.0f));
      out.pixels[i * 4 + 3] = 255;
    }
    return out;
  }

 private:
  uint32_t width_, height_;
  std::vector<float> rgb_;  // display values in [0, 1], white to start
};

struct Coverage {
  PlotColour colour;
  double amount;
};

void draw(Canvas& canvas, const PlotLine& line, const Font&) {
  const double dx = line.x1 - line.x0, dy = line.y1 - line.y0;
  const double length_squared = dx * dx + dy * dy;
  canvas.shade_box(
      std::min(line.x0, line.x1), std::min(line.y0, line.y1), std::max(line.x0, line.x1),
      std::max(line.y0, line.y1), line.width + 1.0, [&](double x, double y) {
        const double t =
            length_squared > 0.0
                ? std::clamp(((x - line.x0) * dx + (y - line.y0) * dy) / length_squared, 0.0, 1.0)
                : 0.0;
        const double distance = std::hypot(x - (line.x0 + t * dx), y - (line.y0 + t * dy));
        return Coverage{line.colour, line.width / 2 + 0.5 - distance};
      });
}

void draw(Canvas& canvas, const PlotDisc& disc, const Font&) {
  canvas.shade_box(disc.x, disc.y, disc.x, disc.y, disc.radius + 1.0, [&](double x, double y) {
    return Coverage{disc.colour, disc.radius + 0.5 - std::hypot(x - disc.x, y - disc.y)};
  });
}

// Glyph by glyph along the baseline from the anchor; text-space pixel (u, v) (v down from the
// baseline) lands at (x + u, y + v) upright, at (x + v, y - u - 1) rotated to read upwards.
void draw(Canvas& canvas, const PlotText& text, const Font& font) {
  const float scale = stbtt_ScaleForMappingEmToPixels(&font.info, float(text.size));
  const std::vector<int> glyphs = code_points(text.text);
  auto advance = [&](size_t i) {
    int advance_width = 0, left_bearing = 0;
    stbtt_GetCodepointHMetrics(&font.info, glyphs[i], &advance_width, &left_bearing);
    const int kern = i + 1 < glyphs.size()
                         ? stbtt_GetCodepointKernAdvance(&font.info, glyphs[i], glyphs[i + 1])
                         : 0;
    return double(advance_width + kern) * scale;
  };
  double width = 0.0;
  for (size_t i = 0; i < glyphs.size(); ++i) width += advance(i);
  double pen = text.anchor == TextAnchor::kStart    ? 0.0
               : text.anchor == TextAnchor::kMiddle ? -width / 2
                                                    : -width;
  const int64_t x = std::lround(text.x), y = std::lround(text.y);
  std::vector<uint8_t> bitmap;
  for (size_t i = 0; i < glyphs.size(); ++i) {
    const double whole = std::floor(pen);
    const float shift = float(pen - whole);
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    stbtt_GetCodepointBitmapBoxSubpixel(&font.info, glyphs[i], scale, scale, shift, 0.0f, &x0, &y0,
                                        &x1, &y1);
    const int w = x1 - x0, h = y1 - y0;
    if (w > 0 && h > 0) {
      bitmap.assign(size_t(w) * size_t(h), 0);
      stbtt_MakeCodepointBitmapSubpixel(&font.info, bitmap.data(), w, h, w, scale, scale, shift,
                                        0.0f, glyphs[i]);
      for (int gy = 0; gy < h; ++gy) {
        for (int gx = 0; gx < w; ++gx) {
          const int64_t u = int64_t(whole) + x0 + gx, v = y0 + gy;
          const double coverage = bitmap[size_t(gy) * size_t(w) + size_t(gx)] / 255.0;
          if (text.vertical) {
            canvas.blend(x + v, y - u - 1, text.colour, coverage);
          } else {
            canvas.blend(x + u, y + v, text.colour, coverage);
          }
        }
      }
    }
    pen += advance(i);
  }
}

}  // namespace

Result<encode::ImageRgba8> rasterize_plot(const PlotDrawing& drawing) {
  DDGI_ASSIGN_OR_RETURN(const Font* font, plot_font());
  Canvas canvas(drawing.width, drawing.height);
  for (const PlotItem& item : drawing.items) {
    std::visit([&](const auto& primitive) { draw(canvas, primitive, *font); }, item);
  }
  return canvas.image();
}

Result<encode::ImageRgba8> scatter_plot_image(const ScatterPlot& plot) {
  return rasterize_plot(lay_out_scatter_plot(plot));
}

}  // namespace ddgi
