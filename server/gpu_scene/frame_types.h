// Choices a frame is made of, shared by the renderer, the fields and the service. Values match
// the kTonemap* / kDirect* / kView* constants of shaders/shared/frame_data.h.
#pragma once

#include <cstdint>
#include <string>

#include "core/result.h"

namespace ddgi {

enum class Tonemap : uint32_t { kClamp = 0, kReinhard = 1, kAces = 2 };
// How direct light from punctual lights is evaluated (per pixel and at probe-ray hits).
// docs/shadow-field.md describes the shadow-field modes.
enum class DirectMode : uint32_t {
  kTracedShadows = 0,
  kUnshadowed = 1,
  kShadowField = 2,       // visibility reconstructed from the shadow field
  kAmbientOcclusion = 3,  // shadow field, plus the sky through the field's AO
  kAoTraced = 4,          // shadow rays, plus the sky through AO traced per pixel (ao_samples)
  kAoCache = 5,           // shadow rays, plus the sky through AO from the world cache
};
enum class View : uint32_t {
  kFull = 0,
  kDirect = 1,
  kIndirect = 2,
  kAlbedo = 3,
  kNormal = 4,
  kProbes = 5,       // the full image with every probe drawn as a sphere shaded by its irradiance
  kAtlas = 6,        // the irradiance atlas over the distance atlas
  kCachePoints = 7,  // ao-cache mode: each surface coloured by the world-cache point it reads
};

Result<Tonemap> parse_tonemap(const std::string& text);
// "shadow-rays", "unshadowed", "shadow-field", "ao", "ao-traced", "ao-cache".
Result<DirectMode> parse_direct_mode(const std::string& text);
const char* direct_mode_name(DirectMode mode);
// Whether `mode` reads a shadow field (the shadow-field and AO modes).
inline bool uses_shadow_field(DirectMode mode) {
  return mode == DirectMode::kShadowField || mode == DirectMode::kAmbientOcclusion;
}
// Whether `mode` reads the world cache (gi/world_cache.h).
inline bool uses_world_cache(DirectMode mode) {
  return mode == DirectMode::kAoCache;
}
Result<View> parse_view(const std::string& text);

}  // namespace ddgi
