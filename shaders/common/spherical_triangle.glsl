// Uniform sampling of the solid angle a triangle subtends (Arvo 1995, "Stratified sampling of
// spherical triangles"): emitter sampling by solid angle instead of by area, so that a surface
// next to an emitter does not get the heavy-tailed 1 / distance^2 weights of area sampling
// (common/emitter_direct.glsl; docs/results/default-energy.md measures the difference).
#ifndef DDGI_COMMON_SPHERICAL_TRIANGLE_GLSL
#define DDGI_COMMON_SPHERICAL_TRIANGLE_GLSL

#include "common/math.glsl"

// The triangle of unit directions (a, b, c) on the sphere around a point, and its solid angle.
struct SphericalTriangle {
  vec3 a, b, c;
  float solid_angle;
};

// Unit vector of `v` orthogonal to unit `n` (the tangent at n of the great arc towards v).
vec3 arc_tangent(vec3 n, vec3 v) {
  return normalize(v - dot(v, n) * n);
}

// The solid angle comes from Van Oosterom and Strackee's formula rather than the angle excess
// alpha + beta + gamma - pi, which cancels to nothing in single precision for small triangles.
SphericalTriangle spherical_triangle(vec3 a, vec3 b, vec3 c) {
  SphericalTriangle t;
  t.a = a;
  t.b = b;
  t.c = c;
  const float triple = abs(dot(a, cross(b, c)));
  t.solid_angle = 2.0 * atan(triple, 1.0 + dot(a, b) + dot(b, c) + dot(c, a));
  return t;
}

// A direction distributed uniformly over the triangle (density 1 / solid_angle) for u in
// [0, 1)^2: u.x picks the sub-triangle (a, b, c') of area u.x x solid_angle, u.y a point on the
// arc from b to c'. The interior angle at a is found here, not with the solid angle: a caller
// that only needs the solid angle (to choose area sampling instead) does not pay for it.
vec3 sample_spherical_triangle(SphericalTriangle t, vec2 u) {
  const float alpha = acos(clamp(dot(arc_tangent(t.a, t.b), arc_tangent(t.a, t.c)), -1.0, 1.0));
  const float area = u.x * t.solid_angle;
  const float s = sin(area - alpha);
  const float c = cos(area - alpha);
  const float cos_alpha = cos(alpha);
  const float sin_alpha = sin(alpha);
  const float p = c - cos_alpha;
  const float q = s + sin_alpha * dot(t.a, t.b);
  // The cosine of the arc from a to c' (the sub-triangle's side b).
  const float cos_b =
      clamp(((q * c - p * s) * cos_alpha - q) / ((q * s + p * c) * sin_alpha), -1.0, 1.0);
  const vec3 c_prime = cos_b * t.a + sqrt(max(0.0, 1.0 - cos_b * cos_b)) * arc_tangent(t.a, t.c);
  const float z = 1.0 - u.y * (1.0 - dot(c_prime, t.b));
  return z * t.b + sqrt(max(0.0, 1.0 - z * z)) * arc_tangent(t.b, c_prime);
}

#endif
