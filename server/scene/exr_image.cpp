#include "scene/exr_image.h"

#include <cmath>
#include <exception>
#include <system_error>

#include <ImfArray.h>
#include <ImfRgbaFile.h>

namespace ddgi {
namespace fs = std::filesystem;

Result<EnvironmentImage> load_exr_environment(const fs::path& path, const SceneLimits& limits,
                                              std::vector<std::string>* warnings) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return not_found(path.string() + ": no such file");
  const uintmax_t bytes = fs::file_size(path, ec);
  if (ec || bytes > limits.max_file_bytes) {
    return resource_exhausted(path.string() + ": larger than the file size limit of " +
                              std::to_string(limits.max_file_bytes) + " bytes");
  }
  try {
    Imf::RgbaInputFile file(path.c_str());
    const Imath::Box2i window = file.dataWindow();
    const int64_t width = int64_t{window.max.x} - window.min.x + 1;
    const int64_t height = int64_t{window.max.y} - window.min.y + 1;
    if (width < 1 || height < 1 || width > limits.max_environment_width ||
        height > limits.max_environment_height) {
      return resource_exhausted(path.string() + ": " + std::to_string(width) + "x" +
                                std::to_string(height) + " is outside 1x1 .. " +
                                std::to_string(limits.max_environment_width) + "x" +
                                std::to_string(limits.max_environment_height));
    }
    Imf::Array2D<Imf::Rgba> pixels(height, width);
    // OpenEXR addresses the frame buffer by data-window coordinates.
    file.setFrameBuffer(&pixels[0][0] - window.min.x - window.min.y * width, 1,
                        static_cast<size_t>(width));
    file.readPixels(window.min.y, window.max.y);

    EnvironmentImage image;
    image.width = static_cast<uint32_t>(width);
    image.height = static_cast<uint32_t>(height);
    image.rgb.resize(static_cast<size_t>(width * height * 3));
    size_t replaced = 0;
    for (int64_t y = 0; y < height; ++y) {
      for (int64_t x = 0; x < width; ++x) {
        const Imf::Rgba& p = pixels[y][x];
        const float rgb[3] = {p.r, p.g, p.b};
        for (int c = 0; c < 3; ++c) {
          float v = rgb[c];
          if (!std::isfinite(v) || v < 0.0f) {
            v = 0.0f;
            ++replaced;
          }
          image.rgb[static_cast<size_t>((y * width + x) * 3 + c)] = v;
        }
      }
    }
    if (replaced > 0) {
      warnings->push_back(path.string() + ": " + std::to_string(replaced) +
                          " negative or non-finite values set to 0");
    }
    return image;
  } catch (const std::exception& e) {
    return invalid_argument(path.string() + ": cannot read the EXR image: " + e.what());
  }
}

}  // namespace ddgi
