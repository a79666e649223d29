// Bilinear upscaling of path-traced images (tools/image_upscale.h).
#include "tools/image_upscale.h"

#include <algorithm>
#include <cmath>

namespace ddgi::tools {
namespace {

// Where output coordinate i (of `to` pixels) samples the source (of `from`): the lower source
// pixel and the weight of the upper one.
struct Tap {
  uint32_t lower = 0, upper = 0;
  float weight = 0.0f;
};

Tap tap(uint32_t i, uint32_t from, uint32_t to) {
  const float source = (float(i) + 0.5f) * float(from) / float(to) - 0.5f;
  const float clamped = std::clamp(source, 0.0f, float(from - 1));
  const uint32_t lower = uint32_t(std::floor(clamped));
  return {lower, std::min(lower + 1, from - 1), clamped - float(lower)};
}

// Resamples RGBA pixels of type T (4 per pixel) with `round` turning a blend back into T.
template <typename T, typename Round>
std::vector<T> resample(const std::vector<T>& pixels, uint32_t from_w, uint32_t from_h,
                        uint32_t to_w, uint32_t to_h, Round round) {
  std::vector<T> out(size_t(to_w) * to_h * 4);
  for (uint32_t y = 0; y < to_h; ++y) {
    const Tap ty = tap(y, from_h, to_h);
    for (uint32_t x = 0; x < to_w; ++x) {
      const Tap tx = tap(x, from_w, to_w);
      auto at = [&](uint32_t sx, uint32_t sy, int c) {
        return float(pixels[(size_t(sy) * from_w + sx) * 4 + size_t(c)]);
      };
      for (int c = 0; c < 4; ++c) {
        const float top =
            at(tx.lower, ty.lower, c) * (1 - tx.weight) + at(tx.upper, ty.lower, c) * tx.weight;
        const float bottom =
            at(tx.lower, ty.upper, c) * (1 - tx.weight) + at(tx.upper, ty.upper, c) * tx.weight;
        out[(size_t(y) * to_w + x) * 4 + size_t(c)] =
            round(top * (1 - ty.weight) + bottom * ty.weight);
      }
    }
  }
  return out;
}

}  // namespace

PathTraceImage upscaled(const PathTraceImage& image, uint32_t width, uint32_t height) {
  PathTraceImage out;
  out.width = width;
  out.height = height;
  out.samples = image.samples;
  out.radiance =
      resample(image.radiance, image.width, image.height, width, height, [](float v) { return v; });
  out.ldr = resample(image.ldr, image.width, image.height, width, height,
                     [](float v) { return uint8_t(std::clamp(std::lround(v), 0L, 255L)); });
  return out;
}

}  // namespace ddgi::tools
