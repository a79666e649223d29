#include "load_image.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

namespace ddgi::client {

namespace {

// In double, so that 1.0 maps to exactly 1.0 (the float version is off by one ulp).
double srgb_encode(double linear) {
  if (linear <= 0.0031308) return 12.92 * linear;
  return 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

}  // namespace

Result<DisplayImage> load_display_image(const std::string& path, double exposure_stops) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    return not_found(path + ": no such file");
  }
  std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(path);
  if (!input) return invalid_argument(path + ": cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = input->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
    return invalid_argument(path + ": image has no pixels");
  }
  const size_t channels = size_t(spec.nchannels);
  const size_t pixels = size_t(spec.width) * size_t(spec.height);
  std::vector<float> data(pixels * channels);
  // OIIO converts integer types to [0,1] floats and leaves float data as-is.
  if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data())) {
    return invalid_argument(path + ": cannot read pixels: " + input->geterror());
  }

  DisplayImage image;
  image.path = path;
  image.width = uint32_t(spec.width);
  image.height = uint32_t(spec.height);
  image.pixel_type = spec.format.c_str();
  image.hdr = spec.format.is_floating_point();
  image.rgb.resize(pixels * 3);
  const double scale = std::exp2(exposure_stops);
  size_t clipped = 0;
  for (size_t p = 0; p < pixels; ++p) {
    for (size_t c = 0; c < 3; ++c) {
      const size_t source = channels < 3 ? 0 : c;  // grey (+ alpha) counts as R = G = B
      const float value = data[p * channels + source];
      if (!std::isfinite(value)) {
        return invalid_argument(path + ": non-finite value at pixel (" +
                                std::to_string(p % image.width) + ", " +
                                std::to_string(p / image.width) + ")");
      }
      double out = value;
      if (image.hdr) {
        const double exposed = value * scale;
        if (exposed > 1.0) ++clipped;
        out = srgb_encode(std::clamp(exposed, 0.0, 1.0));
      }
      image.rgb[p * 3 + c] = static_cast<float>(out);
    }
  }
  image.clipped_fraction = double(clipped) / double(pixels * 3);
  return image;
}

}  // namespace ddgi::client
