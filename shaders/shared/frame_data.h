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
DDGI_CONST uint kFrameBindingYuv420 = 3;    // uint words: the LDR image as Y, Cb, Cr planes

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
// Traced shadow rays + the sky through AO traced per pixel (ao_samples rays): the reference.
DDGI_CONST uint kDirectAoTraced = 4u;
// Traced shadow rays + the sky through AO read from the world cache (shared/world_cache_data.h).
DDGI_CONST uint kDirectAoCache = 5u;

// DirectConstants::flags
DDGI_CONST uint kDirectAddSky = 1u;  // AO modes: add the sky term (no irradiance field brings it)
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
DDGI_CONST uint kViewCachePoints = 7u;  // surfaces coloured by the world-cache point they read

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
  uint ao_samples;       // kDirectAoTraced: AO rays per pixel
  float ao_distance;     // the world cache's AO modes: longer AO rays are open
};

struct IndirectConstants {
  vec3 camera_position;
  uint view;
  uint width;
  uint height;
  uint paths;          // pixel_paths.glsl: paths per pixel (field parameter pixel_paths)
  uint path_vertices;  // ... and their vertices (pixel_path_vertices)
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

// The LDR image as JPEG's YCbCr (JFIF: full-range BT.601) with 4:2:0 chroma, three planes in
// one buffer; yuv420.comp writes it, libjpeg-turbo compresses it without converting colours.
// Sizes in bytes; strides and offsets are multiples of 4, so the kernel writes whole words.
// frame_target.h's yuv420_layout() is the one place they are computed.
struct Yuv420Layout {
  uint width;          // image pixels
  uint height;
  uint y_stride;       // bytes per Y row: the width rounded up to 8 (an invocation: 8x2 pixels)
  uint chroma_stride;  // bytes per Cb or Cr row: y_stride / 2
  uint y_rows;         // the height rounded up to 2; chroma planes have half as many rows
  uint cb_offset;      // y_stride * y_rows: the Y plane starts at 0
  uint cr_offset;      // cb_offset + chroma_stride * y_rows / 2
  uint total_bytes;    // cr_offset + chroma_stride * y_rows / 2
};

#ifdef __cplusplus
// C++ only: the byte layout GLSL gives these structs (scalar block layout), member by member, so
// that the C++ and GLSL views of a struct cannot drift apart. A failure means a struct changed:
// check that the GLSL side agrees (same header), then update the numbers here.
static_assert(sizeof(GBufferTexel) == 40);
static_assert(offsetof(GBufferTexel, position) == 0);
static_assert(offsetof(GBufferTexel, normal_oct) == 12);
static_assert(offsetof(GBufferTexel, emission) == 16);
static_assert(offsetof(GBufferTexel, geometric_normal_oct) == 28);
static_assert(offsetof(GBufferTexel, albedo_flags) == 32);

static_assert(sizeof(PrimaryConstants) == 64);
static_assert(offsetof(PrimaryConstants, camera_position) == 0);
static_assert(offsetof(PrimaryConstants, width) == 12);
static_assert(offsetof(PrimaryConstants, camera_forward) == 16);
static_assert(offsetof(PrimaryConstants, height) == 28);
static_assert(offsetof(PrimaryConstants, camera_right) == 32);
static_assert(offsetof(PrimaryConstants, tmin) == 44);
static_assert(offsetof(PrimaryConstants, camera_up) == 48);
static_assert(offsetof(PrimaryConstants, tmax) == 60);

static_assert(sizeof(DirectConstants) == 48);
static_assert(offsetof(DirectConstants, width) == 0);
static_assert(offsetof(DirectConstants, height) == 4);
static_assert(offsetof(DirectConstants, mode) == 8);
static_assert(offsetof(DirectConstants, view) == 12);
static_assert(offsetof(DirectConstants, camera_position) == 16);
static_assert(offsetof(DirectConstants, light_samples) == 28);
static_assert(offsetof(DirectConstants, flags) == 32);
static_assert(offsetof(DirectConstants, emitter_samples) == 36);
static_assert(offsetof(DirectConstants, ao_samples) == 40);
static_assert(offsetof(DirectConstants, ao_distance) == 44);

static_assert(sizeof(IndirectConstants) == 32);
static_assert(offsetof(IndirectConstants, camera_position) == 0);
static_assert(offsetof(IndirectConstants, view) == 12);
static_assert(offsetof(IndirectConstants, width) == 16);
static_assert(offsetof(IndirectConstants, height) == 20);
static_assert(offsetof(IndirectConstants, paths) == 24);
static_assert(offsetof(IndirectConstants, path_vertices) == 28);

static_assert(sizeof(FieldViewConstants) == 64);
static_assert(offsetof(FieldViewConstants, camera_position) == 0);
static_assert(offsetof(FieldViewConstants, view) == 12);
static_assert(offsetof(FieldViewConstants, camera_forward) == 16);
static_assert(offsetof(FieldViewConstants, width) == 28);
static_assert(offsetof(FieldViewConstants, camera_right) == 32);
static_assert(offsetof(FieldViewConstants, height) == 44);
static_assert(offsetof(FieldViewConstants, camera_up) == 48);
static_assert(offsetof(FieldViewConstants, probe_radius) == 60);

static_assert(sizeof(TonemapConstants) == 16);
static_assert(offsetof(TonemapConstants, width) == 0);
static_assert(offsetof(TonemapConstants, height) == 4);
static_assert(offsetof(TonemapConstants, tonemap) == 8);
static_assert(offsetof(TonemapConstants, exposure) == 12);
static_assert(sizeof(Yuv420Layout) == 32);  // eight uints, no padding in either language
#endif

DDGI_NAMESPACE_END

#endif
