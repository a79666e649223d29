#include "encode/write_image.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "encode/exr.h"
#include "encode/file_io.h"
#include "encode/png.h"

namespace ddgi::encode {

namespace {

std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return extension;
}

Status write_8bit(const std::string& path, ImageFormat format, const ImageRgba8& image,
                  const WriteOptions& options) {
  Result<std::vector<uint8_t>> bytes =
      format == ImageFormat::kPng ? encode_png(image)
                                  : encode_jpeg(image, options.jpeg_quality, options.jpeg_chroma);
  if (!bytes.ok()) return bytes.error().with_context(path);
  return write_file(path, *bytes);
}

}  // namespace

Result<ImageFormat> format_from_path(const std::string& path) {
  const std::string extension = lower_extension(path);
  if (extension == ".jpg" || extension == ".jpeg") return ImageFormat::kJpeg;
  if (extension == ".png") return ImageFormat::kPng;
  if (extension == ".exr") return ImageFormat::kExr;
  return invalid_argument(path + ": unknown image extension '" + extension +
                          "' (expected .jpg, .jpeg, .png or .exr)");
}

Status write_image(const std::string& path, const ImageRgba8& image, const WriteOptions& options) {
  DDGI_ASSIGN_OR_RETURN(const ImageFormat format, format_from_path(path));
  if (Status valid = validate(image); !valid.ok()) return valid.error().with_context(path);
  if (format == ImageFormat::kExr) return write_exr(path, to_linear(image));
  return write_8bit(path, format, image, options);
}

Status write_image(const std::string& path, const ImageRgbF& image, const WriteOptions& options) {
  DDGI_ASSIGN_OR_RETURN(const ImageFormat format, format_from_path(path));
  if (Status valid = validate(image); !valid.ok()) return valid.error().with_context(path);
  if (format == ImageFormat::kExr) return write_exr(path, image);
  return write_8bit(path, format, to_srgb8(image), options);
}

}  // namespace ddgi::encode
