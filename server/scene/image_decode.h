// PNG and JPEG, the two image formats core glTF allows, decoded with stb_image. The header is
// read first so that an image claiming absurd dimensions is refused before any allocation.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/result.h"

namespace ddgi {

struct ImageSize {
  uint32_t width = 0;
  uint32_t height = 0;
  uint64_t rgba8_bytes() const { return uint64_t{width} * height * 4; }
};

// Reads only the header; fails for other formats, unreadable headers and images larger than
// max_dimension on either side.
Result<ImageSize> probe_image(std::span<const uint8_t> encoded, uint32_t max_dimension);

// Decodes to RGBA8, rows top to bottom; `expected` is what probe_image returned.
Result<std::vector<uint8_t>> decode_rgba8(std::span<const uint8_t> encoded, ImageSize expected);

}  // namespace ddgi
