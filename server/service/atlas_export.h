// Probe-atlas dumps: texels of the fields' atlases (irradiance, distance, shadow visibility,
// shadow moments) or the probe states, as a lossless EXR (32-bit float, ZIP) or raw
// little-endian floats, with metadata that makes the dump self-describing (grid, spacing, texels
// per probe, border, encoding gamma, update index). The EXR carries the same metadata as
// "ddgi.*" string attributes, so a file alone is enough to interpret it.
#pragma once

#include <cstdint>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"
#include "gi/irradiance_field.h"
#include "gi/shadow_field.h"
#include "vk/context.h"
#include "vk/resources.h"

namespace ddgi::service {

using AtlasImage = IrradianceField::AtlasImage;

// What a DumpAtlas asks for (kind and format already validated).
struct AtlasRequest {
  v1::AtlasKind kind = v1::ATLAS_KIND_IRRADIANCE;
  v1::AtlasFormat format = v1::ATLAS_FORMAT_EXR;
  uint32_t volume = 0;  // of the irradiance field (FieldParams.volumes); checked here
};

// The dump of `request.kind` with its metadata (total_bytes not yet set): for the irradiance
// field's kinds, the probes of one volume as a grid of its own; `shadow` may be null (then the
// shadow kinds are FAILED_PRECONDITION).
Result<std::pair<v1::AtlasMetadata, AtlasImage>> read_atlas(vk::Context& context,
                                                            IrradianceField* field,
                                                            ShadowField* shadow,
                                                            const AtlasRequest& request);

// The dump's bytes; sets metadata.total_bytes.
Result<std::vector<uint8_t>> encode_atlas(const AtlasImage& image, v1::AtlasMetadata& metadata);

}  // namespace ddgi::service
