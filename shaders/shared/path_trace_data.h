// The reference path tracer's kernel interface (server/render/path_tracer.h).
// Its set 1 uses the frame set's radiance/LDR binding numbers so that the frame's tone-mapping
// kernel can run on the path tracer's accumulation buffer unchanged.
#ifndef DDGI_SHARED_PATH_TRACE_DATA_H
#define DDGI_SHARED_PATH_TRACE_DATA_H

#include "shared/interop.h"

DDGI_NAMESPACE_BEGIN

DDGI_CONST uint kPathTraceSet = 1;
DDGI_CONST uint kPathTraceBindingRadiance = 1;  // vec4 per pixel: running mean (rgb), 1
DDGI_CONST uint kPathTraceBindingLdr = 2;       // uint per pixel: tone-mapped sRGB RGBA8

// What the accumulated image holds (PathTraceConstants::view); docs/reference-path-tracer.md.
DDGI_CONST uint kPathTraceFull = 0u;
DDGI_CONST uint kPathTraceDirect = 1u;          // emission seen + light from sources at hit 1
DDGI_CONST uint kPathTraceIndirect = 2u;        // full - direct
DDGI_CONST uint kPathTracePunctualDirect = 3u;  // emission seen + punctual lights at hit 1
DDGI_CONST uint kPathTraceFieldIndirect = 4u;   // full - punctual direct

struct PathTraceConstants {
  vec3 camera_position;
  uint width;
  vec3 camera_forward;  // unit
  uint height;
  vec3 camera_right;    // scaled: tan(yfov/2) * aspect
  float tmin;
  vec3 camera_up;       // scaled: tan(yfov/2)
  uint view;
  uint seed;
  uint first_sample;    // samples already in the accumulation buffer
  uint sample_count;    // samples this dispatch adds per pixel
  uint max_bounces;     // scattering events per path (0: emission seen by the camera only)
  uint roulette_start;  // Russian roulette from this bounce on
  uint jitter;          // 1: random position inside the pixel; 0: the pixel centre
  uint pad0;
  uint pad1;
};

#ifdef __cplusplus
// C++ only: the byte layout GLSL gives these structs (scalar block layout), member by member, so
// that the C++ and GLSL views of a struct cannot drift apart. A failure means a struct changed:
// check that the GLSL side agrees (same header), then update the numbers here.
static_assert(sizeof(PathTraceConstants) == 96);
static_assert(offsetof(PathTraceConstants, camera_position) == 0);
static_assert(offsetof(PathTraceConstants, width) == 12);
static_assert(offsetof(PathTraceConstants, camera_forward) == 16);
static_assert(offsetof(PathTraceConstants, height) == 28);
static_assert(offsetof(PathTraceConstants, camera_right) == 32);
static_assert(offsetof(PathTraceConstants, tmin) == 44);
static_assert(offsetof(PathTraceConstants, camera_up) == 48);
static_assert(offsetof(PathTraceConstants, view) == 60);
static_assert(offsetof(PathTraceConstants, seed) == 64);
static_assert(offsetof(PathTraceConstants, first_sample) == 68);
static_assert(offsetof(PathTraceConstants, sample_count) == 72);
static_assert(offsetof(PathTraceConstants, max_bounces) == 76);
static_assert(offsetof(PathTraceConstants, roulette_start) == 80);
static_assert(offsetof(PathTraceConstants, jitter) == 84);
static_assert(offsetof(PathTraceConstants, pad0) == 88);
static_assert(offsetof(PathTraceConstants, pad1) == 92);
#endif

DDGI_NAMESPACE_END

#endif
