// Client-side conversion of probe-atlas dumps (EXR or raw float32 from DumpAtlas) to any format
// OpenImageIO writes: float formats (.exr, .tif, .hdr, .pfm) keep the values; 8-bit formats
// (.png, .jpg, ...) get a preview: irradiance (already perceptually encoded) and visibility
// clamped to [0,1]; distances, shadow moments and probe states scaled by their largest finite
// value per channel.
#pragma once

#include <string>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"

namespace ddgi::client {

struct AtlasTexels {
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t channels = 0;
  std::vector<float> values;  // interleaved, row 0 = top
};

// The texels of a dump as received: raw bytes are checked against the metadata's size.
Result<AtlasTexels> atlas_texels(const v1::AtlasMetadata& metadata, const std::string& bytes,
                                 const std::string& saved_path);

Status convert_atlas(const AtlasTexels& texels, v1::AtlasKind kind, const std::string& path);

}  // namespace ddgi::client
