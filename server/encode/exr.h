// OpenEXR for linear HDR output: what the renderer computes, before any exposure or tone curve.
#pragma once

#include <string>

#include "core/result.h"
#include "encode/image.h"

namespace ddgi::encode {

// Writes R, G, B as 32-bit FLOAT channels with lossless ZIP compression. FLOAT rather than HALF
// because half tops out at 65504 and loses everything under ~6e-8 (and is only 11-bit precise),
// while radiance buffers hold both; with FLOAT every value, including 1e-6, 1e6, +-inf and NaN,
// comes back bit-exact. Errors name the file.
Status write_exr(const std::string& path, const ImageRgbF& image);

// Reads the R, G and B channels of a scanline or tiled EXR of any pixel type (HALF and UINT are
// converted to float); a file without all three is INVALID_ARGUMENT. The data window is what is
// returned (its origin is dropped). Errors name the file.
Result<ImageRgbF> read_exr(const std::string& path);

}  // namespace ddgi::encode
