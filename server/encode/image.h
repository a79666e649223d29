// The two in-memory image types the encoders accept: 8-bit display images (what a viewer sees)
// and linear float images (what the renderer computes, before exposure and tone mapping).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"

namespace ddgi::encode {

// sRGB-encoded RGBA, 4 bytes per pixel, row-major, top row first.
struct ImageRgba8 {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> pixels;
};

// An 8-bit image as JPEG's YCbCr (JFIF: full-range BT.601) with 4:2:0 chroma, in one buffer:
// a Y plane of the width and height rounded up to even (libjpeg-turbo reads that much: the
// padding column and row must hold the edge's values, or they bleed into the visible pixels'
// DCT blocks) and Cb, Cr planes of ceil(width/2) x ceil(height/2); each row `stride` bytes
// after the last. The renderer writes it on the GPU (FrameSettings::read_yuv420) so the JPEG
// encoder need not convert colours.
struct ImageYuv420 {
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t y_stride = 0;       // bytes per Y row, >= width rounded up to even
  uint32_t chroma_stride = 0;  // bytes per Cb or Cr row, >= ceil(width/2)
  size_t cb_offset = 0;        // the Y plane starts at byte 0
  size_t cr_offset = 0;
  std::vector<uint8_t> bytes;
};

// Linear (scene-referred) RGB, 3 floats per pixel, row-major, top row first. Values may exceed
// 1 (HDR); they are not clamped until something converts them for display.
struct ImageRgbF {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<float> rgb;
};

// Decoders refuse larger images so a hostile header cannot make us allocate gigabytes.
inline constexpr uint64_t kMaxDecodePixels = uint64_t{1} << 27;  // 134 M pixels, 512 MiB RGBA

// "640x480", the form every size-related error message uses.
std::string size_string(uint32_t width, uint32_t height);

// Non-empty and the buffer holds exactly width * height pixels.
Status validate(const ImageRgba8& image);
Status validate(const ImageRgbF& image);
// Non-empty, strides wide enough, planes apart and inside the buffer.
Status validate(const ImageYuv420& image);

// The sRGB transfer function (IEC 61966-2-1), both directions, on values in [0,1].
float srgb_to_linear(float encoded);
float linear_to_srgb(float linear);

// RGBA8 -> YCbCr 4:2:0 on the CPU with the narrowest rows (stride = plane width): the
// arithmetic of shaders/render/yuv420.comp (JFIF matrix in float, chroma from each 2x2 block's
// mean RGB, edges repeated into the padding, rounded half up), so it is that kernel's
// reference. Alpha is dropped.
ImageYuv420 to_yuv420(const ImageRgba8& image);

// Linear -> 8-bit sRGB with no tone mapping: values are clamped to [0,1] (NaN becomes 0), so
// apply exposure or a tone curve first if the image is HDR. Alpha is 255.
ImageRgba8 to_srgb8(const ImageRgbF& image);
// 8-bit sRGB -> linear float, exact inverse of the transfer function; alpha is dropped.
ImageRgbF to_linear(const ImageRgba8& image);
// Drops the alpha of RGBA floats (the renderer's and path tracer's HDR buffers), for EXR.
ImageRgbF rgb_from_rgba(uint32_t width, uint32_t height, const std::vector<float>& rgba);

}  // namespace ddgi::encode
