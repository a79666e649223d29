#include "metrics/colormap.h"

#include <algorithm>
#include <cmath>

namespace ddgi::metrics {

namespace {

// Hand-picked anchors, evenly spaced in t, whose luma rises strictly from one to the next;
// colours between anchors are linear blends in sRGB.
constexpr std::array<std::array<float, 3>, 9> kAnchors = {{
    {0.0f, 0.0f, 4.0f},
    {28.0f, 16.0f, 68.0f},
    {80.0f, 18.0f, 123.0f},
    {130.0f, 38.0f, 129.0f},
    {182.0f, 54.0f, 122.0f},
    {230.0f, 82.0f, 98.0f},
    {251.0f, 136.0f, 97.0f},
    {254.0f, 195.0f, 135.0f},
    {252.0f, 253.0f, 191.0f},
}};

}  // namespace

std::array<uint8_t, 3> error_color(float t) {
  if (!(t > 0.0f)) t = 0.0f;  // also catches NaN
  t = std::min(t, 1.0f);
  const float position = t * static_cast<float>(kAnchors.size() - 1);
  const size_t lower = std::min(static_cast<size_t>(position), kAnchors.size() - 2);
  const float blend = position - static_cast<float>(lower);
  std::array<uint8_t, 3> out{};
  for (size_t c = 0; c < 3; ++c) {
    const float value = kAnchors[lower][c] + blend * (kAnchors[lower + 1][c] - kAnchors[lower][c]);
    out[c] = static_cast<uint8_t>(std::lround(value));
  }
  return out;
}

std::vector<uint8_t> colorize_errors(std::span<const float> errors) {
  std::vector<uint8_t> pixels(errors.size() * 4);
  for (size_t i = 0; i < errors.size(); ++i) {
    const std::array<uint8_t, 3> color = error_color(errors[i]);
    std::copy(color.begin(), color.end(), pixels.begin() + static_cast<std::ptrdiff_t>(i * 4));
    pixels[i * 4 + 3] = 255;
  }
  return pixels;
}

}  // namespace ddgi::metrics
