#include "gpu_scene/frame_types.h"

#include "shared/frame_data.h"

namespace ddgi {

// The kernels read these enums as the frame_data.h constants.
static_assert(uint32_t(Tonemap::kClamp) == gpu::kTonemapClamp);
static_assert(uint32_t(Tonemap::kReinhard) == gpu::kTonemapReinhard);
static_assert(uint32_t(Tonemap::kAces) == gpu::kTonemapAces);
static_assert(uint32_t(DirectMode::kTracedShadows) == gpu::kDirectTracedShadows);
static_assert(uint32_t(DirectMode::kUnshadowed) == gpu::kDirectUnshadowed);
static_assert(uint32_t(DirectMode::kShadowField) == gpu::kDirectShadowField);
static_assert(uint32_t(DirectMode::kAmbientOcclusion) == gpu::kDirectAmbientOcclusion);
static_assert(uint32_t(DirectMode::kAoTraced) == gpu::kDirectAoTraced);
static_assert(uint32_t(DirectMode::kAoCache) == gpu::kDirectAoCache);
static_assert(uint32_t(View::kFull) == gpu::kViewFull);
static_assert(uint32_t(View::kDirect) == gpu::kViewDirect);
static_assert(uint32_t(View::kIndirect) == gpu::kViewIndirect);
static_assert(uint32_t(View::kAlbedo) == gpu::kViewAlbedo);
static_assert(uint32_t(View::kNormal) == gpu::kViewNormal);
static_assert(uint32_t(View::kProbes) == gpu::kViewProbes);
static_assert(uint32_t(View::kAtlas) == gpu::kViewAtlas);
static_assert(uint32_t(View::kCachePoints) == gpu::kViewCachePoints);

Result<Tonemap> parse_tonemap(const std::string& text) {
  if (text == "clamp") return Tonemap::kClamp;
  if (text == "reinhard") return Tonemap::kReinhard;
  if (text == "aces") return Tonemap::kAces;
  return invalid_argument("tonemap must be one of clamp, reinhard, aces (got '" + text + "')");
}

Result<DirectMode> parse_direct_mode(const std::string& text) {
  if (text == "shadow-rays") return DirectMode::kTracedShadows;
  if (text == "unshadowed") return DirectMode::kUnshadowed;
  if (text == "shadow-field") return DirectMode::kShadowField;
  if (text == "ao") return DirectMode::kAmbientOcclusion;
  if (text == "ao-traced") return DirectMode::kAoTraced;
  if (text == "ao-cache") return DirectMode::kAoCache;
  return invalid_argument(
      "direct mode must be one of shadow-rays, unshadowed, shadow-field, ao, ao-traced, ao-cache "
      "(got '" +
      text + "')");
}

const char* direct_mode_name(DirectMode mode) {
  switch (mode) {
    case DirectMode::kTracedShadows:
      return "shadow-rays";
    case DirectMode::kUnshadowed:
      return "unshadowed";
    case DirectMode::kShadowField:
      return "shadow-field";
    case DirectMode::kAmbientOcclusion:
      return "ao";
    case DirectMode::kAoTraced:
      return "ao-traced";
    case DirectMode::kAoCache:
      return "ao-cache";
  }
  return "unknown";
}

Result<View> parse_view(const std::string& text) {
  if (text == "full") return View::kFull;
  if (text == "direct") return View::kDirect;
  if (text == "indirect") return View::kIndirect;
  if (text == "albedo") return View::kAlbedo;
  if (text == "normal") return View::kNormal;
  if (text == "probes") return View::kProbes;
  if (text == "atlas") return View::kAtlas;
  if (text == "cache-points") return View::kCachePoints;
  return invalid_argument(
      "view must be one of full, direct, indirect, albedo, normal, probes, atlas, cache-points "
      "(got '" +
      text + "')");
}

}  // namespace ddgi
