#include "encode/image.h"

#include <algorithm>
#include <cmath>

namespace ddgi::encode {

std::string size_string(uint32_t width, uint32_t height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

namespace {

Status validate_size(uint32_t width, uint32_t height, size_t values, size_t per_pixel) {
  if (width == 0 || height == 0) {
    return invalid_argument("image is empty (" + size_string(width, height) + ")");
  }
  const size_t expected = size_t{width} * height * per_pixel;
  if (values != expected) {
    return invalid_argument("image buffer holds " + std::to_string(values) + " values but " +
                            size_string(width, height) + " needs " + std::to_string(expected));
  }
  return ok_status();
}

}  // namespace

Status validate(const ImageRgba8& image) {
  return validate_size(image.width, image.height, image.pixels.size(), 4);
}

Status validate(const ImageRgbF& image) {
  return validate_size(image.width, image.height, image.rgb.size(), 3);
}

Status validate(const ImageYuv420& image) {
  if (image.width == 0 || image.height == 0) {
    return invalid_argument("image is empty (" + size_string(image.width, image.height) + ")");
  }
  // What libjpeg-turbo reads of each plane (tjCompressFromYUVPlanes): even Y sizes.
  const uint32_t y_width = (image.width + 1) / 2 * 2, y_rows = (image.height + 1) / 2 * 2;
  if (image.y_stride < y_width || image.chroma_stride < y_width / 2) {
    return invalid_argument("YUV 4:2:0 rows of " + std::to_string(image.y_stride) + " (Y) and " +
                            std::to_string(image.chroma_stride) + " (chroma) bytes cannot hold " +
                            size_string(image.width, image.height) + " (" +
                            std::to_string(y_width) + " and " + std::to_string(y_width / 2) +
                            " needed)");
  }
  const size_t y_bytes = size_t{image.y_stride} * y_rows;
  const size_t chroma_bytes = size_t{image.chroma_stride} * (y_rows / 2);
  if (image.cb_offset < y_bytes || image.cr_offset < image.cb_offset + chroma_bytes ||
      image.bytes.size() < image.cr_offset + chroma_bytes) {
    return invalid_argument("YUV 4:2:0 planes of " + size_string(image.width, image.height) +
                            " overlap or run past the buffer's " +
                            std::to_string(image.bytes.size()) + " bytes");
  }
  return ok_status();
}

namespace {

uint8_t to_byte(float value) {
  return static_cast<uint8_t>(std::clamp(std::floor(value + 0.5f), 0.0f, 255.0f));
}

}  // namespace

ImageYuv420 to_yuv420(const ImageRgba8& image) {
  const uint32_t w = image.width, h = image.height;
  const uint32_t chroma_w = (w + 1) / 2, chroma_h = (h + 1) / 2;
  const uint32_t y_w = chroma_w * 2, y_h = chroma_h * 2;  // with the padding column and row
  const size_t y_bytes = size_t{y_w} * y_h, chroma_bytes = size_t{chroma_w} * chroma_h;
  ImageYuv420 yuv{w,
                  h,
                  y_w,
                  chroma_w,
                  y_bytes,
                  y_bytes + chroma_bytes,
                  std::vector<uint8_t>(y_bytes + 2 * chroma_bytes)};
  auto rgb = [&](uint32_t x, uint32_t y, int channel) {
    return float(image.pixels[(size_t{std::min(y, h - 1)} * w + std::min(x, w - 1)) * 4 + channel]);
  };
  for (uint32_t y = 0; y < y_h; ++y) {
    for (uint32_t x = 0; x < y_w; ++x) {
      yuv.bytes[size_t{y} * y_w + x] =
          to_byte(rgb(x, y, 0) * 0.299f + rgb(x, y, 1) * 0.587f + rgb(x, y, 2) * 0.114f);
    }
  }
  for (uint32_t cy = 0; cy < chroma_h; ++cy) {
    for (uint32_t cx = 0; cx < chroma_w; ++cx) {
      float mean[3];
      for (int c = 0; c < 3; ++c) {
        mean[c] = (rgb(2 * cx, 2 * cy, c) + rgb(2 * cx + 1, 2 * cy, c) +
                   rgb(2 * cx, 2 * cy + 1, c) + rgb(2 * cx + 1, 2 * cy + 1, c)) *
                  0.25f;
      }
      const size_t at = size_t{cy} * chroma_w + cx;
      yuv.bytes[yuv.cb_offset + at] =
          to_byte(128.0f - 0.168736f * mean[0] - 0.331264f * mean[1] + 0.5f * mean[2]);
      yuv.bytes[yuv.cr_offset + at] =
          to_byte(128.0f + 0.5f * mean[0] - 0.418688f * mean[1] - 0.081312f * mean[2]);
    }
  }
  return yuv;
}

float srgb_to_linear(float encoded) {
  if (encoded <= 0.04045f) return encoded / 12.92f;
  return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float linear) {
  if (linear <= 0.0031308f) return linear * 12.92f;
  // In double so that 1 maps to exactly 1 (in float it lands one ulp short).
  return static_cast<float>(1.055 * std::pow(double{linear}, 1.0 / 2.4) - 0.055);
}

ImageRgba8 to_srgb8(const ImageRgbF& image) {
  ImageRgba8 out{image.width, image.height, {}};
  const size_t count = size_t{image.width} * image.height;
  out.pixels.resize(count * 4);
  for (size_t i = 0; i < count; ++i) {
    for (size_t c = 0; c < 3; ++c) {
      float value = image.rgb[i * 3 + c];
      // The negated comparison also catches NaN.
      value = !(value > 0.0f) ? 0.0f : std::min(value, 1.0f);
      out.pixels[i * 4 + c] = static_cast<uint8_t>(std::lround(linear_to_srgb(value) * 255.0f));
    }
    out.pixels[i * 4 + 3] = 255;
  }
  return out;
}

ImageRgbF to_linear(const ImageRgba8& image) {
  ImageRgbF out{image.width, image.height, {}};
  const size_t count = size_t{image.width} * image.height;
  out.rgb.resize(count * 3);
  for (size_t i = 0; i < count; ++i) {
    for (size_t c = 0; c < 3; ++c) {
      out.rgb[i * 3 + c] = srgb_to_linear(static_cast<float>(image.pixels[i * 4 + c]) / 255.0f);
    }
  }
  return out;
}

ImageRgbF rgb_from_rgba(uint32_t width, uint32_t height, const std::vector<float>& rgba) {
  ImageRgbF out{width, height, {}};
  out.rgb.reserve(rgba.size() / 4 * 3);
  for (size_t i = 0; i + 3 < rgba.size(); i += 4) {
    out.rgb.insert(out.rgb.end(), &rgba[i], &rgba[i + 3]);
  }
  return out;
}

}  // namespace ddgi::encode
