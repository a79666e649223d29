// PNG through stb_image_write / stb_image (the system libstb): lossless 8-bit output.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/result.h"
#include "encode/image.h"

namespace ddgi::encode {

// Lossless RGBA PNG (alpha kept).
Result<std::vector<uint8_t>> encode_png(const ImageRgba8& image);

// Any 8-bit PNG -> RGBA (grey and RGB are expanded; 16-bit is reduced to 8).
Result<ImageRgba8> decode_png(std::span<const uint8_t> bytes);

}  // namespace ddgi::encode
