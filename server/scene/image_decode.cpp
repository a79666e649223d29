#include "scene/image_decode.h"

#include <algorithm>
#include <climits>
#include <cstring>
#include <string>

#include <stb_image.h>
#include <turbojpeg.h>

namespace ddgi {
namespace {

bool is_png(std::span<const uint8_t> b) {
  static const uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  return b.size() >= 8 && std::memcmp(b.data(), kSignature, 8) == 0;
}

bool is_jpeg(std::span<const uint8_t> b) {
  return b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF;
}

// JPEG goes through libjpeg-turbo, not stb_image: stb's JPEG decoder reads past a Huffman
// table on hostile input (found by our fuzzer: stb_image.h:1990, index 257 out of bounds),
// while libjpeg-turbo is hardened by years of continuous fuzzing.
class JpegDecoder {
 public:
  JpegDecoder() : handle_(tjInitDecompress()) {}
  ~JpegDecoder() {
    if (handle_) tjDestroy(handle_);
  }
  JpegDecoder(const JpegDecoder&) = delete;
  JpegDecoder& operator=(const JpegDecoder&) = delete;

  Result<ImageSize> header(std::span<const uint8_t> encoded) {
    if (!handle_) return internal_error("cannot create a JPEG decoder");
    int width = 0, height = 0, subsampling = 0, colorspace = 0;
    if (tjDecompressHeader3(handle_, encoded.data(), static_cast<unsigned long>(encoded.size()),
                            &width, &height, &subsampling, &colorspace) != 0) {
      return invalid_argument(std::string("cannot read the JPEG header: ") +
                              tjGetErrorStr2(handle_));
    }
    if (width < 1 || height < 1) return invalid_argument("JPEG image has no pixels");
    return ImageSize{static_cast<uint32_t>(width), static_cast<uint32_t>(height)};
  }

  Result<std::vector<uint8_t>> decode(std::span<const uint8_t> encoded, ImageSize size) {
    std::vector<uint8_t> rgba(size.rgba8_bytes());
    if (tjDecompress2(handle_, encoded.data(), static_cast<unsigned long>(encoded.size()),
                      rgba.data(), static_cast<int>(size.width), 0, static_cast<int>(size.height),
                      TJPF_RGBA, TJFLAG_ACCURATEDCT) != 0 &&
        tjGetErrorCode(handle_) == TJERR_FATAL) {
      return invalid_argument(std::string("cannot decode the JPEG image: ") +
                              tjGetErrorStr2(handle_));
    }
    return rgba;
  }

 private:
  tjhandle handle_;
};

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
  if (is_jpeg(encoded)) {
    DDGI_ASSIGN_OR_RETURN(const ImageSize size, JpegDecoder().header(encoded));
    width = static_cast<int>(std::min<uint32_t>(size.width, INT_MAX));
    height = static_cast<int>(std::min<uint32_t>(size.height, INT_MAX));
  } else if (!stbi_info_from_memory(encoded.data(), static_cast<int>(encoded.size()), &width,
                                    &height, &channels)) {
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
  if (is_jpeg(encoded)) return JpegDecoder().decode(encoded, expected);
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
