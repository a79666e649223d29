// The shadow field on the GPU (docs/shadow-field.md): a probe grid of its own whose octahedral
// maps store, per probe and direction, how visible each kept light is from the surface the probe
// sees that way, plus the distance moments that tell a shading point whether the probe sees it.
//
// GLSL kernels pick the set the sampling resources live in with DDGI_SHADOW_FIELD_SET (the
// field's own update kernels and the frame's direct pass use 2; the irradiance field's probe-ray
// shading, which samples the irradiance field as set 2, uses 3).
#ifndef DDGI_SHARED_SHADOW_FIELD_DATA_H
#define DDGI_SHARED_SHADOW_FIELD_DATA_H

#include "shared/interop.h"

DDGI_NAMESPACE_BEGIN

// Lights one field keeps: one channel each in RGBA visibility texels, groups of four stacked
// vertically in the visibility atlas. Lights past the kept ones follow the overflow policy.
DDGI_CONST uint kShadowMaxLights = 8u;
DDGI_CONST uint kShadowLightsPerGroup = 4u;
DDGI_CONST uint kShadowMaxGroups = 2u;

// Atlas layout: probe p's tile is (p % tiles_per_row, p / tiles_per_row), plus tile_rows x group
// rows down in the visibility atlas; a tile is the octahedral map plus a one-texel border copied
// from the opposite edges (as the irradiance field's).
DDGI_CONST uint kShadowAtlasBorder = 1u;
DDGI_CONST uint kShadowMaxAtlasDimension = 16384u;  // guaranteed by every Vulkan 1.2 device

// The sampling set (set DDGI_SHADOW_FIELD_SET of kernels that sample the field).
DDGI_CONST uint kShadowBindingConstants = 0;   // ShadowFieldConstants (one)
DDGI_CONST uint kShadowBindingVisibility = 1;  // sampler2D RGBA32F: light visibility, 4 per group
DDGI_CONST uint kShadowBindingMoments = 2;     // sampler2D RGBA32F: mean distance, mean squared
                                               // distance, ambient occlusion, visibility weight

// Set 1 of the field's update kernels.
DDGI_CONST uint kShadowUpdateSet = 1;
DDGI_CONST uint kShadowUpdateBindingRays = 0;           // ShadowRay per probe ray
DDGI_CONST uint kShadowUpdateBindingVisibilityOut = 1;  // image2D view of the visibility atlas
DDGI_CONST uint kShadowUpdateBindingMomentsOut = 2;     // image2D view of the moments atlas

// ShadowFieldConstants::flags
DDGI_CONST uint kShadowResetHistory = 1u;  // no valid history: the next blend replaces
DDGI_CONST uint kShadowTraceAo = 2u;       // this update traces and blends ambient occlusion
DDGI_CONST uint kShadowCosineWeights = 4u; // sampling weighs probes by max(0, n.dir), else wrap
DDGI_CONST uint kShadowOverflowTraced = 8u; // lights past the kept ones get traced shadow rays
DDGI_CONST uint kShadowResetAo = 16u;       // AO has no valid history: this update replaces it

// ShadowDispatch::mode bits of the tracing kernel.
DDGI_CONST uint kShadowPassShadow = 1u;   // shadow (and AO) rays from the stored surfels
DDGI_CONST uint kShadowPassPrimary = 2u;  // new probe rays; their surfels replace the stored ones

// ShadowSurfel::flags and ShadowResult::flags
DDGI_CONST uint kShadowRayValid = 1u;      // holds data (a reset clears every record)
DDGI_CONST uint kShadowRayHit = 2u;        // the probe ray hit a surface
DDGI_CONST uint kShadowRayFrontFace = 4u;  // ... its front side

// What a probe ray found. In a split update it waits one update for its shadow rays.
struct ShadowSurfel {
  vec3 position;
  uint flags;        // kShadowRay*
  vec3 direction;    // of the probe ray (its update's rotation)
  float distance;    // hit distance; max_ray_distance on a miss
  uint normal_oct;   // geometric normal on the side the probe sees
  uint pad0;
  uint pad1;
  uint pad2;
};

// What the blend reads: a surfel with its light visibilities.
struct ShadowResult {
  vec3 direction;
  float distance;
  uint flags;        // kShadowRay*
  float ao;          // 1: the AO ray escaped (only when kShadowTraceAo)
  uint pad0;
  uint pad1;
  vec4 visibility[kShadowMaxGroups];  // per kept light, in [0, 1]
};

struct ShadowRay {
  ShadowSurfel surfel;
  ShadowResult result;
};

struct ShadowFieldConstants {
  vec3 origin;
  uint rays_per_probe;
  vec3 spacing;
  uint probe_count;
  ivec3 counts;
  uint texels;                 // interior side of every octahedral map
  uint tiles_per_row;
  uint tile_rows;              // rows of tiles in one light group
  uint light_count;            // lights kept in the atlas: min(scene lights, max_lights)
  uint scene_light_count;      // all lights of the scene
  vec2 atlas_size;             // texels of both atlases (the visibility atlas holds every group)
  uint update_index;
  uint flags;                  // kShadow* flags above
  float hysteresis;
  float visibility_exponent;   // blend weight max(0, w.r)^this for visibility and AO
  float distance_exponent;     // blend weight for the distance moments
  float normal_bias;           // x spacing: shading points move this far along the normal
  float view_bias;             // x spacing: ... and this far towards the viewer
  float sharpening;            // sampled visibility is raised to this power
  float max_ray_distance;
  float max_visibility_distance;
  float ao_distance;           // AO rays longer than this count as open sky
  float weight_crush_threshold;
  float backface_distance_scale;
  uint seed;                   // of the light and AO jitter
  mat4 ray_rotation;           // this update's rotation of the probe rays
};

// Push constants of the field's linear kernels.
struct ShadowDispatch {
  uint count;       // invocations
  uint row_width;   // invocations per row of the folded dispatch
  uint mode;        // kShadowPass* (tracing kernel)
  uint per_probe;   // invocations per probe
};

// The query kernel (tests, the eval tool): field and traced visibility at given points.
DDGI_CONST uint kShadowQuerySet = 1;
DDGI_CONST uint kShadowQueryBindingQueries = 0;  // ShadowQuery per point
DDGI_CONST uint kShadowQueryBindingAnswers = 1;  // ShadowAnswer per point

struct ShadowQuery {
  vec3 position;
  uint traced_samples;  // shadow rays per light for the traced answer (spherical lights)
  vec3 normal;          // unit
  uint ao_samples;      // cosine-distributed rays for the traced AO answer
  vec3 to_viewer;       // unit
  uint seed;
};

struct ShadowAnswer {
  vec4 field_visibility[kShadowMaxGroups];   // per kept light
  vec4 traced_visibility[kShadowMaxGroups];  // per light (first kShadowMaxLights lights)
  float field_ao;
  float traced_ao;
  float weight_sum;     // of the probes that answered (0: no probe could; visibility is 1)
  float pad0;
};

#ifdef __cplusplus
// C++ only: how the constants above fit together.
static_assert(kShadowMaxLights == kShadowLightsPerGroup * kShadowMaxGroups);

// C++ only: the byte layout GLSL gives these structs (scalar block layout), member by member, so
// that the C++ and GLSL views of a struct cannot drift apart. A failure means a struct changed:
// check that the GLSL side agrees (same header), then update the numbers here.
static_assert(sizeof(ShadowSurfel) == 48);
static_assert(offsetof(ShadowSurfel, position) == 0);
static_assert(offsetof(ShadowSurfel, flags) == 12);
static_assert(offsetof(ShadowSurfel, direction) == 16);
static_assert(offsetof(ShadowSurfel, distance) == 28);
static_assert(offsetof(ShadowSurfel, normal_oct) == 32);
static_assert(offsetof(ShadowSurfel, pad0) == 36);
static_assert(offsetof(ShadowSurfel, pad1) == 40);
static_assert(offsetof(ShadowSurfel, pad2) == 44);

static_assert(sizeof(ShadowResult) == 64);
static_assert(offsetof(ShadowResult, direction) == 0);
static_assert(offsetof(ShadowResult, distance) == 12);
static_assert(offsetof(ShadowResult, flags) == 16);
static_assert(offsetof(ShadowResult, ao) == 20);
static_assert(offsetof(ShadowResult, pad0) == 24);
static_assert(offsetof(ShadowResult, pad1) == 28);
static_assert(offsetof(ShadowResult, visibility) == 32);

static_assert(sizeof(ShadowRay) == 112);
static_assert(offsetof(ShadowRay, surfel) == 0);
static_assert(offsetof(ShadowRay, result) == 48);

static_assert(sizeof(ShadowFieldConstants) == 192);
static_assert(offsetof(ShadowFieldConstants, origin) == 0);
static_assert(offsetof(ShadowFieldConstants, rays_per_probe) == 12);
static_assert(offsetof(ShadowFieldConstants, spacing) == 16);
static_assert(offsetof(ShadowFieldConstants, probe_count) == 28);
static_assert(offsetof(ShadowFieldConstants, counts) == 32);
static_assert(offsetof(ShadowFieldConstants, texels) == 44);
static_assert(offsetof(ShadowFieldConstants, tiles_per_row) == 48);
static_assert(offsetof(ShadowFieldConstants, tile_rows) == 52);
static_assert(offsetof(ShadowFieldConstants, light_count) == 56);
static_assert(offsetof(ShadowFieldConstants, scene_light_count) == 60);
static_assert(offsetof(ShadowFieldConstants, atlas_size) == 64);
static_assert(offsetof(ShadowFieldConstants, update_index) == 72);
static_assert(offsetof(ShadowFieldConstants, flags) == 76);
static_assert(offsetof(ShadowFieldConstants, hysteresis) == 80);
static_assert(offsetof(ShadowFieldConstants, visibility_exponent) == 84);
static_assert(offsetof(ShadowFieldConstants, distance_exponent) == 88);
static_assert(offsetof(ShadowFieldConstants, normal_bias) == 92);
static_assert(offsetof(ShadowFieldConstants, view_bias) == 96);
static_assert(offsetof(ShadowFieldConstants, sharpening) == 100);
static_assert(offsetof(ShadowFieldConstants, max_ray_distance) == 104);
static_assert(offsetof(ShadowFieldConstants, max_visibility_distance) == 108);
static_assert(offsetof(ShadowFieldConstants, ao_distance) == 112);
static_assert(offsetof(ShadowFieldConstants, weight_crush_threshold) == 116);
static_assert(offsetof(ShadowFieldConstants, backface_distance_scale) == 120);
static_assert(offsetof(ShadowFieldConstants, seed) == 124);
static_assert(offsetof(ShadowFieldConstants, ray_rotation) == 128);

static_assert(sizeof(ShadowDispatch) == 16);
static_assert(offsetof(ShadowDispatch, count) == 0);
static_assert(offsetof(ShadowDispatch, row_width) == 4);
static_assert(offsetof(ShadowDispatch, mode) == 8);
static_assert(offsetof(ShadowDispatch, per_probe) == 12);

static_assert(sizeof(ShadowQuery) == 48);
static_assert(offsetof(ShadowQuery, position) == 0);
static_assert(offsetof(ShadowQuery, traced_samples) == 12);
static_assert(offsetof(ShadowQuery, normal) == 16);
static_assert(offsetof(ShadowQuery, ao_samples) == 28);
static_assert(offsetof(ShadowQuery, to_viewer) == 32);
static_assert(offsetof(ShadowQuery, seed) == 44);

static_assert(sizeof(ShadowAnswer) == 80);
static_assert(offsetof(ShadowAnswer, field_visibility) == 0);
static_assert(offsetof(ShadowAnswer, traced_visibility) == 32);
static_assert(offsetof(ShadowAnswer, field_ao) == 64);
static_assert(offsetof(ShadowAnswer, traced_ao) == 68);
static_assert(offsetof(ShadowAnswer, weight_sum) == 72);
static_assert(offsetof(ShadowAnswer, pad0) == 76);
#endif

DDGI_NAMESPACE_END

#endif
