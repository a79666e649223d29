// Internal to encode/: YUV 4:2:0 planes by pointer, so a strip of an image (jpeg_strips.cpp)
// compresses without a copy, and the checks both JPEG encoders run first.
#pragma once

#include <cstdint>
#include <vector>

#include "core/result.h"
#include "encode/image.h"

namespace ddgi::encode {

struct Yuv420Planes {
  const uint8_t* y = nullptr;
  const uint8_t* cb = nullptr;
  const uint8_t* cr = nullptr;
  uint32_t y_stride = 0;
  uint32_t chroma_stride = 0;
  uint32_t width = 0;
  uint32_t height = 0;  // Y rows read: height rounded up to even (ImageYuv420's padding)
};

// The whole of a validated image.
Yuv420Planes yuv420_planes(const ImageYuv420& image);

// Quality in 1..100 and sides JPEG can hold.
Status check_jpeg_input(uint32_t width, uint32_t height, int quality);

// TurboJPEG's compression of planes already checked.
Result<std::vector<uint8_t>> compress_yuv420_planes(const Yuv420Planes& planes, int quality);

}  // namespace ddgi::encode
