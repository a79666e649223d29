#include "atlas_convert.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ddgi::client {
namespace {

bool is_float_format(const std::string& path) {
  std::string ext = path.substr(
      path.find_last_of('.') == std::string::npos ? path.size() : path.find_last_of('.'));
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext == ".exr" || ext == ".tif" || ext == ".tiff" || ext == ".hdr" || ext == ".pfm";
}

}  // namespace

Result<AtlasTexels> atlas_texels(const v1::AtlasMetadata& metadata, const std::string& bytes,
                                 const std::string& saved_path) {
  AtlasTexels texels;
  texels.width = metadata.width();
  texels.height = metadata.height();
  texels.channels = static_cast<uint32_t>(metadata.channels_size());
  if (texels.channels == 0 || texels.channels > 4 || texels.width == 0 || texels.height == 0) {
    return invalid_argument("atlas metadata describes no image");
  }
  const size_t values = size_t(texels.width) * texels.height * texels.channels;
  if (metadata.format() == v1::ATLAS_FORMAT_RAW_F32) {
    if (bytes.size() != values * sizeof(float)) {
      return invalid_argument("raw atlas has " + std::to_string(bytes.size()) +
                              " bytes; its metadata promises " +
                              std::to_string(values * sizeof(float)));
    }
    texels.values.resize(values);
    std::memcpy(texels.values.data(), bytes.data(), bytes.size());
    return texels;
  }
  // EXR: read back the file just written.
  std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(saved_path);
  if (!input) return invalid_argument(saved_path + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = input->spec();
  if (uint32_t(spec.width) != texels.width || uint32_t(spec.height) != texels.height ||
      uint32_t(spec.nchannels) != texels.channels) {
    return invalid_argument(saved_path + ": size or channels differ from the metadata");
  }
  texels.values.resize(values);
  if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, texels.values.data())) {
    return invalid_argument(saved_path + ": " + input->geterror());
  }
  return texels;
}

Status convert_atlas(const AtlasTexels& texels, v1::AtlasKind kind, const std::string& path) {
  const bool keep_floats = is_float_format(path);
  // 8-bit previews: RGB only; distance moments scaled to the largest finite value per channel.
  const uint32_t out_channels = keep_floats ? texels.channels : 3;
  std::vector<float> scale(texels.channels, 1.0f);
  // Distances, moments and probe offsets: scaled to their largest value (visibility, irradiance
  // and AO are in [0, 1] already).
  const bool scale_to_max = kind == v1::ATLAS_KIND_DISTANCE ||
                            kind == v1::ATLAS_KIND_SHADOW_MOMENTS ||
                            kind == v1::ATLAS_KIND_PROBE_STATES || kind == v1::ATLAS_KIND_SH;
  if (!keep_floats && scale_to_max) {
    for (uint32_t c = 0; c < texels.channels; ++c) {
      float largest = 0.0f;
      for (size_t i = c; i < texels.values.size(); i += texels.channels) {
        if (std::isfinite(texels.values[i])) largest = std::max(largest, texels.values[i]);
      }
      scale[c] = largest > 0.0f ? 1.0f / largest : 1.0f;
    }
  }
  const size_t pixels = size_t(texels.width) * texels.height;
  std::vector<float> out(pixels * out_channels, 0.0f);
  for (size_t p = 0; p < pixels; ++p) {
    for (uint32_t c = 0; c < std::min(out_channels, texels.channels); ++c) {
      float v = texels.values[p * texels.channels + c] * scale[c];
      if (!keep_floats) v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
      out[p * out_channels + c] = v;
    }
  }
  std::unique_ptr<OIIO::ImageOutput> output = OIIO::ImageOutput::create(path);
  if (!output) return invalid_argument(path + ": " + OIIO::geterror());
  OIIO::ImageSpec spec(int(texels.width), int(texels.height), int(out_channels),
                       keep_floats ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!output->open(path, spec) || !output->write_image(OIIO::TypeDesc::FLOAT, out.data()) ||
      !output->close()) {
    return unavailable(path + ": " + output->geterror());
  }
  return ok_status();
}

}  // namespace ddgi::client
