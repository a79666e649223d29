#include "encode/png.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <climits>
#include <memory>
#include <string>

namespace ddgi::encode {

namespace {

void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  const auto* begin = static_cast<const uint8_t*>(data);
  out->insert(out->end(), begin, begin + size);
}

struct StbFreer {
  void operator()(unsigned char* pixels) const { stbi_image_free(pixels); }
};

}  // namespace

Result<std::vector<uint8_t>> encode_png(const ImageRgba8& image) {
  DDGI_TRY(validate(image));
  // stb takes int sizes and an int row stride.
  if (image.width > INT_MAX / 4 || image.height > INT_MAX) {
    return invalid_argument("image too large for PNG: " + size_string(image.width, image.height));
  }
  std::vector<uint8_t> bytes;
  const int width = static_cast<int>(image.width);
  if (stbi_write_png_to_func(append_bytes, &bytes, width, static_cast<int>(image.height), 4,
                             image.pixels.data(), width * 4) == 0) {
    return internal_error("PNG encoding failed for a " + size_string(image.width, image.height) +
                          " image");
  }
  return bytes;
}

Result<ImageRgba8> decode_png(std::span<const uint8_t> bytes) {
  if (bytes.empty()) return invalid_argument("PNG data is empty");
  if (bytes.size() > size_t{INT_MAX}) return invalid_argument("PNG data is over 2 GiB");
  // stb_image sniffs many formats; insist on PNG's signature so a JPEG is not accepted here.
  static constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < sizeof(kSignature) ||
      !std::equal(kSignature, kSignature + sizeof(kSignature), bytes.begin())) {
    return invalid_argument("not a PNG (bad signature)");
  }
  const auto* data = bytes.data();
  const int size = static_cast<int>(bytes.size());
  int width = 0;
  int height = 0;
  int channels = 0;
  if (stbi_info_from_memory(data, size, &width, &height, &channels) == 0) {
    return invalid_argument(std::string("not a readable PNG: ") + stbi_failure_reason());
  }
  if (uint64_t(width) * uint64_t(height) > kMaxDecodePixels) {
    return resource_exhausted("PNG is " + size_string(uint32_t(width), uint32_t(height)) +
                              ", over the decoder's pixel limit");
  }
  std::unique_ptr<unsigned char, StbFreer> pixels(
      stbi_load_from_memory(data, size, &width, &height, &channels, 4));
  if (!pixels)
    return invalid_argument(std::string("PNG decoding failed: ") + stbi_failure_reason());
  ImageRgba8 image{uint32_t(width), uint32_t(height), {}};
  image.pixels.assign(pixels.get(), pixels.get() + size_t(width) * size_t(height) * 4);
  return image;
}

}  // namespace ddgi::encode
