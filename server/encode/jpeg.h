// JPEG through libjpeg-turbo's TurboJPEG API: the fast path for streaming frames to clients.
#pragma once

#include <cstdint>
#include <functional>
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

// Runs body(0) .. body(count - 1), possibly at once, and returns when all have run.
using ParallelFor = std::function<void(size_t count, const std::function<void(size_t)>& body)>;

// The same JPEG as encode_jpeg(image, quality), cut into up to `max_strips` horizontal strips
// of whole 16-pixel MCU rows that compress independently (through `parallel_for`) and are
// joined into one baseline JPEG with restart markers between them: a decoder gives exactly the
// pixels of the one-piece encode (a restart only resets the DC predictors, which a new strip
// starts from anyway); the file grows by a few bytes per strip. A 1080p frame's encode time
// then falls with the cores. Strips are at least kMinStripMcuRows MCU rows (128 pixels) tall.
inline constexpr uint32_t kMinStripMcuRows = 8;
Result<std::vector<uint8_t>> encode_jpeg_strips(const ImageYuv420& image, int quality,
                                                uint32_t max_strips,
                                                const ParallelFor& parallel_for);

// Any baseline/progressive JPEG -> RGBA with alpha 255; refuses images over kMaxDecodePixels.
Result<ImageRgba8> decode_jpeg(std::span<const uint8_t> bytes);

}  // namespace ddgi::encode
