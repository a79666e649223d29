#include "encode/jpeg.h"

#include "encode/jpeg_planes.h"

#include <turbojpeg.h>

#include <memory>
#include <string>

namespace ddgi::encode {

namespace {

struct TjDestroyer {
  void operator()(void* handle) const { tjDestroy(handle); }
};
using TjHandle = std::unique_ptr<void, TjDestroyer>;

// Frees the buffer TurboJPEG allocates for compressed output.
struct TjFreer {
  void operator()(unsigned char* buffer) const { tjFree(buffer); }
};

// JPEG stores dimensions in 16 bits.
constexpr uint32_t kMaxJpegDimension = 65535;

}  // namespace

Status check_jpeg_input(uint32_t width, uint32_t height, int quality) {
  if (quality < 1 || quality > 100) {
    return invalid_argument("JPEG quality must be in 1..100, got " + std::to_string(quality));
  }
  if (width > kMaxJpegDimension || height > kMaxJpegDimension) {
    return invalid_argument("JPEG cannot hold a " + size_string(width, height) +
                            " image (65535 pixels per side at most)");
  }
  return ok_status();
}

namespace {

// Runs one TurboJPEG compression (`compress` is called with the handle and the output
// pointers) and returns its bytes.
template <typename Compress>
Result<std::vector<uint8_t>> compress_with(Compress compress) {
  TjHandle handle(tjInitCompress());
  if (!handle)
    return internal_error(std::string("tjInitCompress failed: ") + tjGetErrorStr2(nullptr));
  unsigned char* raw_output = nullptr;
  unsigned long output_size = 0;
  const int status = compress(handle.get(), &raw_output, &output_size);
  std::unique_ptr<unsigned char, TjFreer> output(raw_output);
  if (status != 0) {
    return internal_error(std::string("JPEG encoding failed: ") + tjGetErrorStr2(handle.get()));
  }
  return std::vector<uint8_t>(output.get(), output.get() + output_size);
}

}  // namespace

Yuv420Planes yuv420_planes(const ImageYuv420& image) {
  const uint8_t* bytes = image.bytes.data();
  return {bytes,          bytes + image.cb_offset, bytes + image.cr_offset,
          image.y_stride, image.chroma_stride,     image.width,
          image.height};
}

Result<std::vector<uint8_t>> encode_jpeg(const ImageRgba8& image, int quality, JpegChroma chroma) {
  DDGI_TRY(check_jpeg_input(image.width, image.height, quality));
  DDGI_TRY(validate(image));
  const int subsampling = chroma == JpegChroma::k444 ? TJSAMP_444 : TJSAMP_420;
  return compress_with([&](tjhandle handle, unsigned char** output, unsigned long* size) {
    return tjCompress2(handle, image.pixels.data(), static_cast<int>(image.width), 0,
                       static_cast<int>(image.height), TJPF_RGBA, output, size, subsampling,
                       quality, 0);
  });
}

Result<std::vector<uint8_t>> compress_yuv420_planes(const Yuv420Planes& planes, int quality) {
  const unsigned char* pointers[3] = {planes.y, planes.cb, planes.cr};
  const int strides[3] = {static_cast<int>(planes.y_stride), static_cast<int>(planes.chroma_stride),
                          static_cast<int>(planes.chroma_stride)};
  return compress_with([&](tjhandle handle, unsigned char** output, unsigned long* size) {
    return tjCompressFromYUVPlanes(handle, pointers, static_cast<int>(planes.width), strides,
                                   static_cast<int>(planes.height), TJSAMP_420, output, size,
                                   quality, 0);
  });
}

Result<std::vector<uint8_t>> encode_jpeg(const ImageYuv420& image, int quality) {
  DDGI_TRY(check_jpeg_input(image.width, image.height, quality));
  DDGI_TRY(validate(image));
  return compress_yuv420_planes(yuv420_planes(image), quality);
}

Result<ImageRgba8> decode_jpeg(std::span<const uint8_t> bytes) {
  if (bytes.empty()) return invalid_argument("JPEG data is empty");
  TjHandle handle(tjInitDecompress());
  if (!handle) {
    return internal_error(std::string("tjInitDecompress failed: ") + tjGetErrorStr2(nullptr));
  }
  int width = 0;
  int height = 0;
  int subsampling = 0;
  int colorspace = 0;
  if (tjDecompressHeader3(handle.get(), bytes.data(), bytes.size(), &width, &height, &subsampling,
                          &colorspace) != 0) {
    return invalid_argument(std::string("not a readable JPEG: ") + tjGetErrorStr2(handle.get()));
  }
  if (width <= 0 || height <= 0) return invalid_argument("JPEG header has an empty image");
  if (uint64_t(width) * uint64_t(height) > kMaxDecodePixels) {
    return resource_exhausted("JPEG is " + size_string(uint32_t(width), uint32_t(height)) +
                              ", over the decoder's pixel limit");
  }
  ImageRgba8 image{uint32_t(width), uint32_t(height), {}};
  image.pixels.resize(size_t(width) * size_t(height) * 4);
  if (tjDecompress2(handle.get(), bytes.data(), bytes.size(), image.pixels.data(), width, 0, height,
                    TJPF_RGBA, 0) != 0) {
    return invalid_argument(std::string("JPEG decoding failed: ") + tjGetErrorStr2(handle.get()));
  }
  return image;
}

}  // namespace ddgi::encode
