// Per-frame passes: the G-buffer, the direct-light pass, tone mapping.
// Descriptor set 1 of the frame kernels.
#ifndef DDGI_SHARED_FRAME_DATA_H
#define DDGI_SHARED_FRAME_DATA_H

#include "shared/interop.h"

DDGI_NAMESPACE_BEGIN

DDGI_CONST uint kFrameSet = 1;
DDGI_CONST uint kFrameBindingGBuffer = 0;   // GBufferTexel per pixel
DDGI_CONST uint kFrameBindingRadiance = 1;  // vec4 per pixel: linear HDR radiance
DDGI_CONST uint kFrameBindingLdr = 2;       // uint per pixel: tone-mapped sRGB RGBA8

// GBufferTexel::albedo_flags.y, bits 16..31.
DDGI_CONST uint kGBufferHit = 1u << 16;        // the primary ray hit a surface
DDGI_CONST uint kGBufferFrontFace = 1u << 17;  // ... its front side

struct GBufferTexel {
  vec3 position;              // world-space hit point
  uint normal_oct;            // shading normal, octahedral 2x16 snorm
  vec3 emission;              // emitted radiance towards the camera, or the environment
  uint geometric_normal_oct;  // face normal on the side the camera sees
  uvec2 albedo_flags;         // half-float linear RGB albedo (x: RG, y low: B) + flags (y high)
};

// Tone-mapping operators (TonemapConstants::tonemap).
DDGI_CONST uint kTonemapClamp = 0u;
DDGI_CONST uint kTonemapReinhard = 1u;
DDGI_CONST uint kTonemapAces = 2u;

// Ways the direct pass evaluates light (DirectConstants::mode).
DDGI_CONST uint kDirectTracedShadows = 0u;
DDGI_CONST uint kDirectUnshadowed = 1u;
DDGI_CONST uint kDirectShadowField = 2u;       // visibility reconstructed from the shadow field
DDGI_CONST uint kDirectAmbientOcclusion = 3u;  // shadow field + the sky through its AO

// DirectConstants::flags
DDGI_CONST uint kDirectAddSky = 1u;  // AO mode: add the sky term (no irradiance field brings it)
// Add emitter light by sampling emissive triangles (the field then carries no emission).
DDGI_CONST uint kDirectSampleEmitters = 2u;

// What the final image shows (DirectConstants::view).
DDGI_CONST uint kViewFull = 0u;
DDGI_CONST uint kViewDirect = 1u;
DDGI_CONST uint kViewIndirect = 2u;
DDGI_CONST uint kViewAlbedo = 3u;
DDGI_CONST uint kViewNormal = 4u;
DDGI_CONST uint kViewProbes = 5u;  // the full image with every probe drawn as a sphere
DDGI_CONST uint kViewAtlas = 6u;   // the irradiance atlas (top) and distance atlas (bottom)

struct PrimaryConstants {
  vec3 camera_position;
  uint width;
  vec3 camera_forward;  // unit
  uint height;
  vec3 camera_right;    // scaled: tan(yfov/2) * aspect
  float tmin;
  vec3 camera_up;       // scaled: tan(yfov/2)
  float tmax;
};

struct DirectConstants {
  uint width;
  uint height;
  uint mode;
  uint view;
  vec3 camera_position;
  uint light_samples;  // shadow rays per spherical light in the traced mode
  uint flags;          // kDirect* flags
  uint emitter_samples;  // kDirectSampleEmitters: emitter samples per pixel
  uint pad1;
  uint pad2;
};

struct IndirectConstants {
  vec3 camera_position;
  uint view;
  uint width;
  uint height;
  uint pad0;
  uint pad1;
};

struct FieldViewConstants {
  vec3 camera_position;
  uint view;
  vec3 camera_forward;
  uint width;
  vec3 camera_right;  // scaled as in PrimaryConstants
  uint height;
  vec3 camera_up;     // scaled as in PrimaryConstants
  float probe_radius;
};

struct TonemapConstants {
  uint width;
  uint height;
  uint tonemap;
  float exposure;  // linear multiplier applied before the operator
};

DDGI_NAMESPACE_END

#endif
