#include "metrics/image_view.h"

#include <cmath>

namespace ddgi::metrics {

namespace {

std::string size_string(const RgbImageView& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

}  // namespace

Status check_image(const RgbImageView& image, const std::string& name) {
  if (image.width == 0 || image.height == 0) {
    return invalid_argument(name + " image is empty (" + size_string(image) + ")");
  }
  const size_t expected = size_t{image.width} * image.height * 3;
  if (image.rgb.size() != expected) {
    return invalid_argument(name + " image buffer holds " + std::to_string(image.rgb.size()) +
                            " floats but " + size_string(image) + " RGB needs " +
                            std::to_string(expected));
  }
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    if (!std::isfinite(image.rgb[i])) {
      const size_t pixel = i / 3;
      return invalid_argument(name + " image has a non-finite value at pixel (" +
                              std::to_string(pixel % image.width) + ", " +
                              std::to_string(pixel / image.width) + ")");
    }
  }
  return ok_status();
}

Status check_pair(const RgbImageView& a, const RgbImageView& b) {
  DDGI_TRY(check_image(a, "first"));
  DDGI_TRY(check_image(b, "second"));
  if (a.width != b.width || a.height != b.height) {
    return invalid_argument("image sizes differ: " + size_string(a) + " vs " + size_string(b));
  }
  return ok_status();
}

}  // namespace ddgi::metrics
