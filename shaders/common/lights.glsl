// Punctual lights (KHR_lights_punctual, taken radiometrically) and direct lighting.
#ifndef DDGI_COMMON_LIGHTS_GLSL
#define DDGI_COMMON_LIGHTS_GLSL

#include "common/trace.glsl"

struct LightSample {
  vec3 direction;   // unit, from the shading point towards the light
  float distance;   // to the light (kFloatMax for directional lights)
  vec3 irradiance;  // at normal incidence, before visibility
};

// glTF's range window: smooth falloff to zero at `range`, none when range is 0.
float range_window(float distance, float range) {
  if (range <= 0.0) return 1.0;
  const float r = distance / range;
  const float r4 = r * r * r * r;
  return clamp(1.0 - r4, 0.0, 1.0);
}

// `jitter` picks a point on a spherical light (ignored for radius 0).
LightSample sample_light(GpuLight light, vec3 p, vec2 jitter) {
  LightSample s;
  if (light.type == kLightDirectional) {
    s.direction = -light.direction;
    s.distance = kFloatMax;
    s.irradiance = light.radiance;
    return s;
  }
  vec3 target = light.position;
  if (light.radius > 0.0) {
    // A uniformly chosen point on the sphere's disc facing p: soft shadows.
    const vec3 axis = safe_normalize(p - light.position, vec3(0, 1, 0));
    vec3 t, b;
    orthonormal_basis(axis, t, b);
    const float r = light.radius * sqrt(jitter.x);
    const float phi = 2.0 * kPi * jitter.y;
    target += r * (cos(phi) * t + sin(phi) * b);
  }
  const vec3 to_light = target - p;
  float d2 = max(dot(to_light, to_light), 1e-30);
  const float largest = max(abs(to_light.x), max(abs(to_light.y), abs(to_light.z)));
  if (largest > 1e18) {
    // The squared distance leaves float range (to_light / inf would be a zero direction):
    // measure a scaled copy so a very distant light keeps its direction and distance.
    const vec3 scaled = to_light / largest;
    s.distance = length(scaled) * largest;
    d2 = s.distance * s.distance;
    s.direction = normalize(scaled);
  } else {
    s.distance = sqrt(d2);
    s.direction = to_light / s.distance;
  }
  // An inverse-square law that stays finite when the point touches the light.
  const float falloff = range_window(s.distance, light.range) /
                        max(d2, light.radius * light.radius + 1e-12);
  float cone = 1.0;
  if (light.type == kLightSpot) {
    const float cd = dot(light.direction, -s.direction);
    const float t = clamp(cd * light.spot_scale + light.spot_offset, 0.0, 1.0);
    cone = t * t;
  }
  s.irradiance = light.radiance * (falloff * cone);
  return s;
}

// Lambertian reflected radiance at a surface from every light. `shadowed`: trace shadow rays.
vec3 direct_lighting(Surface s, bool shadowed, inout Rng rng) {
  vec3 sum = vec3(0.0);
  const vec3 origin = offset_ray_origin(s.position, s.geometric_normal);
  for (uint i = 0u; i < scene.light_count; ++i) {
    const GpuLight light = scene_lights[i];
    const vec2 jitter = light.radius > 0.0 ? vec2(rng_next(rng), rng_next(rng)) : vec2(0.0);
    const LightSample ls = sample_light(light, s.position, jitter);
    const float cos_theta = dot(s.normal, ls.direction);
    if (cos_theta <= 0.0 || dot(s.geometric_normal, ls.direction) <= 0.0) continue;
    if (all(equal(ls.irradiance, vec3(0.0)))) continue;
    vec3 visibility = vec3(1.0);
    if (shadowed) {
      // Stop just short of the light so a light on a surface is not blocked by it.
      const float tmax = ls.distance == kFloatMax ? kFloatMax : ls.distance * (1.0 - 1e-4);
      visibility = trace_transmittance(origin, ls.direction, 0.0, tmax);
    }
    sum += ls.irradiance * cos_theta * visibility;
  }
  return sanitize_radiance(sum * s.albedo * kInvPi);
}

#endif
