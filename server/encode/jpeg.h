// JPEG through libjpeg-turbo's TurboJPEG API: the fast path for streaming frames to clients.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/result.h"
#include "encode/image.h"

namespace ddgi::encode {

// Chroma subsampling: 4:2:0 halves the colour resolution (smaller files, what browsers and
// cameras use); 4:4:4 keeps it (sharper coloured edges, larger files).
enum class JpegChroma { k420, k444 };

// quality is libjpeg's 1..100 scale; anything else is INVALID_ARGUMENT. Alpha is dropped.
Result<std::vector<uint8_t>> encode_jpeg(const ImageRgba8& image, int quality,
                                         JpegChroma chroma = JpegChroma::k420);

// The same from planes already in JPEG's colour space (no conversion, 4:2:0 chroma).
Result<std::vector<uint8_t>> encode_jpeg(const ImageYuv420& image, int quality);

// Any baseline/progressive JPEG -> RGBA with alpha 255; refuses images over kMaxDecodePixels.
Result<ImageRgba8> decode_jpeg(std::span<const uint8_t> bytes);

}  // namespace ddgi::encode
