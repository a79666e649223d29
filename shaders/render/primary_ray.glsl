// The camera ray of a pixel (through its centre), shared by primary visibility and its
// benchmark baseline (primary_raw_trace).
#ifndef DDGI_RENDER_PRIMARY_RAY_GLSL
#define DDGI_RENDER_PRIMARY_RAY_GLSL

#include "shared/frame_data.h"

layout(push_constant, scalar) uniform Push { PrimaryConstants pc; };

vec3 primary_ray_direction(uvec2 pixel) {
  const vec2 ndc = (vec2(pixel) + 0.5) / vec2(pc.width, pc.height) * 2.0 - 1.0;
  return normalize(pc.camera_forward + ndc.x * pc.camera_right - ndc.y * pc.camera_up);
}

#endif
