// Sampling routines of the reference path tracer.
#ifndef DDGI_COMMON_SAMPLING_GLSL
#define DDGI_COMMON_SAMPLING_GLSL

#include "common/math.glsl"

// Rec. 709 luminance (server/gpu_scene/emitter_table.cpp weighs emitters with the same one).
float luminance(vec3 c) { return dot(max(c, vec3(0.0)), vec3(0.2126, 0.7152, 0.0722)); }

float max_component(vec3 c) { return max(c.x, max(c.y, c.z)); }

// Cosine-weighted direction about unit n (Malley's method); density cos(theta) / pi.
vec3 sample_cosine_hemisphere(vec3 n, vec2 u) {
  const float r = sqrt(u.x);
  const float phi = 2.0 * kPi * u.y;
  vec3 t, b;
  orthonormal_basis(n, t, b);
  const float z = sqrt(max(0.0, 1.0 - u.x));
  return normalize(r * cos(phi) * t + r * sin(phi) * b + z * n);
}

// Uniformly distributed barycentrics (b1, b2) on a triangle, in the convention of Hit.
vec2 sample_triangle(vec2 u) {
  const float s = sqrt(u.x);
  return vec2(s * (1.0 - u.y), s * u.y);
}

// Veach's power heuristic (beta = 2): the weight of the strategy with density `a`.
float power_heuristic(float a, float b) {
  const float a2 = a * a;
  const float b2 = b * b;
  return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}

#endif
