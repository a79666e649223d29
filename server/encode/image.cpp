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
