// Shadow and AO rays from a surface point: what the shadow field blends into its maps and what
// the query kernel compares it against. Needs a tracing kernel (common/trace.glsl).
#ifndef DDGI_GI_SHADOW_RAYS_GLSL
#define DDGI_GI_SHADOW_RAYS_GLSL

#include "common/lights.glsl"
#include "common/sampling.glsl"

// Visibility in [0, 1] of one light from point `p` with geometric normal `n` (facing the side
// that is shaded): 0 when the light is behind the surface, else the transmittance of one shadow
// ray to a point on the light (`jitter` picks it on spherical lights), averaged over colour.
// Zero-radiance lights cost no ray: their visibility is 1 (nothing to shadow).
float shadow_ray_visibility(vec3 p, vec3 n, GpuLight light, vec2 jitter) {
  if (all(equal(light.radiance, vec3(0.0)))) return 1.0;
  const LightSample ls = sample_light(light, p, jitter);
  if (!(dot(n, ls.direction) > 0.0)) return 0.0;
  // Stop just short of the light so a light on a surface is not blocked by it.
  const float tmax = ls.distance >= kFloatMax ? kFloatMax : ls.distance * (1.0 - 1e-4);
  const vec3 t = trace_transmittance(offset_ray_origin(p, n), ls.direction, 0.0, tmax);
  return clamp(dot(t, vec3(1.0 / 3.0)), 0.0, 1.0);
}

// 1 when a cosine-distributed ray (from `u`) leaves `p` without hitting anything closer than
// `max_distance`: the estimator of ambient occlusion's open fraction.
float ao_ray_open(vec3 p, vec3 n, vec2 u, float max_distance) {
  const vec3 d = sample_cosine_hemisphere(n, u);
  if (!(dot(d, n) > 0.0)) return 0.0;
  const vec3 t = trace_transmittance(offset_ray_origin(p, n), d, 0.0, max_distance);
  return clamp(dot(t, vec3(1.0 / 3.0)), 0.0, 1.0);
}

#endif
