// Reads any image OpenImageIO understands and brings it to the one space ddgi-compare measures
// in: display-encoded (sRGB) RGB in [0,1].
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"

namespace ddgi::client {

struct DisplayImage {
  std::string path;
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<float> rgb;         // sRGB-encoded, [0,1], 3 per pixel
  std::string pixel_type;         // the file's pixel type as OIIO names it: "uint8", "half"...
  bool hdr = false;               // floating-point file, taken as linear and converted
  double clipped_fraction = 0.0;  // HDR only: share of values above 1 after exposure
};

// Integer pixel types (8/16-bit PNG, JPEG, TIFF) are taken as already display-encoded and only
// scaled to [0,1]. Floating-point types (EXR, HDR, float TIFF) are taken as linear HDR and
// converted as sRGB_OETF(clamp(value * 2^exposure_stops, 0, 1)), a plain exposure-and-clip with
// no tone curve, so the numbers describe what a viewer without tone mapping would see.
// Grey images are replicated to RGB; channels after the third (alpha) are ignored. Non-finite
// values are an error naming the file and pixel.
Result<DisplayImage> load_display_image(const std::string& path, double exposure_stops);

}  // namespace ddgi::client
