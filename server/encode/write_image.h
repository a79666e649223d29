// One entry point that picks the encoder from the file extension, for tools and the service.
#pragma once

#include <string>

#include "core/result.h"
#include "encode/image.h"
#include "encode/jpeg.h"

namespace ddgi::encode {

enum class ImageFormat { kJpeg, kPng, kExr };

// .jpg/.jpeg -> JPEG, .png -> PNG, .exr -> EXR (case-insensitive); anything else is
// INVALID_ARGUMENT naming the file and the extensions we know.
Result<ImageFormat> format_from_path(const std::string& path);

struct WriteOptions {
  int jpeg_quality = 90;  // artefacts hard to see on renders, far below PNG size
  JpegChroma jpeg_chroma = JpegChroma::k420;  // the common default; use k444 for sharp UI text
};

// 8-bit image: PNG and JPEG as-is; EXR stores the sRGB-decoded linear values (alpha dropped).
Status write_image(const std::string& path, const ImageRgba8& image,
                   const WriteOptions& options = {});

// Linear float image: EXR as-is; PNG and JPEG get to_srgb8(), i.e. clamped to [0,1] with no tone
// mapping, so expose or tone-map HDR images before writing them to an 8-bit format.
Status write_image(const std::string& path, const ImageRgbF& image,
                   const WriteOptions& options = {});

}  // namespace ddgi::encode
