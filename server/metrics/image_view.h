// The one input type of every metric: a borrowed RGB float buffer. Each metric states what the
// values mean (range, sRGB-encoded or linear); this type only carries the layout.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "core/result.h"

namespace ddgi::metrics {

// 3 floats per pixel (R, G, B), row-major, top row first, no padding.
struct RgbImageView {
  uint32_t width = 0;
  uint32_t height = 0;
  std::span<const float> rgb;
};

// Non-empty, buffer size matches, every value finite (NaN/inf would silently poison a mean).
// `name` ("reference", "test") goes into the message.
Status check_image(const RgbImageView& image, const std::string& name);

// Both images valid and the same size; a mismatch names both sizes ("64x48 vs 32x32").
Status check_pair(const RgbImageView& a, const RgbImageView& b);

}  // namespace ddgi::metrics
