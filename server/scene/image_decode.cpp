#include "scene/image_decode.h"

#include <climits>
#include <cstring>
#include <string>

#include <stb_image.h>

namespace ddgi {
namespace {

bool is_png(std::span<const uint8_t> b) {
  static const uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  return b.size() >= 8 && std::memcmp(b.data(), kSignature, 8) == 0;
}

bool is_jpeg(std::span<const uint8_t> b) {
  return b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF;
}

}  // namespace

Result<ImageSize> probe_image(std::span<const uint8_t> encoded, uint32_t max_dimension) {
  // stb_image reads other formats too; refusing them keeps its less-used decoders away from
  // untrusted bytes.
  if (!is_png(encoded) && !is_jpeg(encoded)) {
    return invalid_argument("not a PNG or JPEG image (the only formats core glTF allows)");
  }
  if (encoded.size() > static_cast<size_t>(INT_MAX)) {
    return resource_exhausted("encoded image of " + std::to_string(encoded.size()) +
                              " bytes is too large to decode");
  }
  int width = 0;
  int height = 0;
  int channels = 0;
  if (!stbi_info_from_memory(encoded.data(), static_cast<int>(encoded.size()), &width, &height,
                             &channels)) {
    return invalid_argument(std::string("cannot read the image header: ") + stbi_failure_reason());
  }
  if (width < 1 || height < 1) {
    return invalid_argument("image has no pixels (" + std::to_string(width) + "x" +
                            std::to_string(height) + ")");
  }
  if (static_cast<uint32_t>(width) > max_dimension ||
      static_cast<uint32_t>(height) > max_dimension) {
    return resource_exhausted("image is " + std::to_string(width) + "x" + std::to_string(height) +
                              " pixels; the limit is " + std::to_string(max_dimension) +
                              " per side");
  }
  return ImageSize{static_cast<uint32_t>(width), static_cast<uint32_t>(height)};
}

Result<std::vector<uint8_t>> decode_rgba8(std::span<const uint8_t> encoded, ImageSize expected) {
  int width = 0;
  int height = 0;
  int channels = 0;
  stbi_uc* pixels = stbi_load_from_memory(encoded.data(), static_cast<int>(encoded.size()), &width,
                                          &height, &channels, 4);
  if (pixels == nullptr) {
    return invalid_argument(std::string("cannot decode the image: ") + stbi_failure_reason());
  }
  if (static_cast<uint32_t>(width) != expected.width ||
      static_cast<uint32_t>(height) != expected.height) {
    stbi_image_free(pixels);
    return invalid_argument("image decoded to a different size than its header says");
  }
  std::vector<uint8_t> rgba(pixels, pixels + expected.rgba8_bytes());
  stbi_image_free(pixels);
  return rgba;
}

}  // namespace ddgi
