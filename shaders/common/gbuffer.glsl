// Packing of G-buffer texels (shared/frame_data.h).
#ifndef DDGI_COMMON_GBUFFER_GLSL
#define DDGI_COMMON_GBUFFER_GLSL

#include "shared/frame_data.h"

uvec2 pack_albedo_flags(vec3 albedo, uint flags) {
  return uvec2(packHalf2x16(albedo.rg), packHalf2x16(vec2(albedo.b, 0.0)) | flags);
}
vec3 unpack_albedo(uvec2 packed) {
  return vec3(unpackHalf2x16(packed.x), unpackHalf2x16(packed.y & 0xFFFFu).x);
}
uint unpack_gbuffer_flags(uvec2 packed) { return packed.y & 0xFFFF0000u; }

#endif
