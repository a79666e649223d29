#include "encode/exr.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <climits>
#include <exception>
#include <filesystem>
#include <string>

namespace ddgi::encode {

namespace {

constexpr const char* kChannels[3] = {"R", "G", "B"};

// OpenEXR reports every failure by exception; this is the boundary where they become values.
Error exr_error(const std::string& path, const std::exception& e) {
  return failed_precondition(path + ": " + e.what());
}

}  // namespace

Status write_exr(const std::string& path, const ImageRgbF& image) {
  if (Status valid = validate(image); !valid.ok()) return valid.error().with_context(path);
  if (image.width > INT_MAX || image.height > INT_MAX) {
    return invalid_argument(path +
                            ": too large for EXR: " + size_string(image.width, image.height));
  }
  try {
    const int width = static_cast<int>(image.width);
    const int height = static_cast<int>(image.height);
    Imf::Header header(width, height);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer frame;
    const size_t pixel_stride = 3 * sizeof(float);
    for (int c = 0; c < 3; ++c) {
      header.channels().insert(kChannels[c], Imf::Channel(Imf::FLOAT));
      // The library only reads through this pointer; its API is not const-correct.
      auto* base = const_cast<float*>(image.rgb.data() + c);
      frame.insert(kChannels[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base), pixel_stride,
                                            pixel_stride * image.width));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(height);
  } catch (const std::exception& e) {
    return exr_error(path, e);
  }
  return ok_status();
}

Result<ImageRgbF> read_exr(const std::string& path) {
  // OpenEXR's own message for a missing file is vague; say it plainly and with the right code.
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return not_found(path + ": no such file");
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const int64_t width = int64_t{window.max.x} - window.min.x + 1;
    const int64_t height = int64_t{window.max.y} - window.min.y + 1;
    if (width <= 0 || height <= 0) return invalid_argument(path + ": empty data window");
    if (uint64_t(width) * uint64_t(height) > kMaxDecodePixels) {
      return resource_exhausted(path + ": " + size_string(uint32_t(width), uint32_t(height)) +
                                " is over the reader's pixel limit");
    }
    const Imf::ChannelList& channels = file.header().channels();
    for (const char* name : kChannels) {
      if (channels.findChannel(name) == nullptr) {
        std::string present;
        for (auto it = channels.begin(); it != channels.end(); ++it) {
          present += std::string(present.empty() ? "" : ", ") + it.name();
        }
        return invalid_argument(path + ": no '" + name + "' channel (has: " + present + ")");
      }
    }
    ImageRgbF image{uint32_t(width), uint32_t(height), {}};
    image.rgb.resize(size_t(width) * size_t(height) * 3);
    Imf::FrameBuffer frame;
    const size_t pixel_stride = 3 * sizeof(float);
    for (int c = 0; c < 3; ++c) {
      // Slice::Make offsets the base pointer by the window origin for us.
      frame.insert(kChannels[c], Imf::Slice::Make(Imf::FLOAT, image.rgb.data() + c, window,
                                                  pixel_stride, pixel_stride * size_t(width)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return image;
  } catch (const std::exception& e) {
    return exr_error(path, e);
  }
}

}  // namespace ddgi::encode
