// Probe-atlas dumps: the field's atlas texels as a lossless EXR (32-bit float, ZIP) or raw
// little-endian floats, with metadata that makes the dump self-describing (grid, spacing,
// texels per probe, border, encoding gamma, update index). The EXR carries the same metadata as
// "ddgi.*" string attributes, so a file alone is enough to interpret it.
#pragma once

#include <cstdint>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"
#include "gi/irradiance_field.h"

namespace ddgi::service {

v1::AtlasMetadata atlas_metadata(const IrradianceField& field, v1::AtlasKind kind,
                                 v1::AtlasFormat format, const IrradianceField::AtlasImage& image);

// The dump's bytes; sets metadata.total_bytes.
Result<std::vector<uint8_t>> encode_atlas(const IrradianceField::AtlasImage& image,
                                          v1::AtlasMetadata& metadata);

}  // namespace ddgi::service
