// Direct light from punctual lights under every DirectMode (shared/frame_data.h kDirect*): the
// frame's direct pass and the irradiance field's probe-ray shading both call direct_light().
// Kernels that bind the shadow field define DDGI_SHADOW_FIELD_SET; in the others the shadow-field
// and AO modes fall back to traced shadow rays (docs/shadow-field.md).
#ifndef DDGI_GI_SHADOW_DIRECT_GLSL
#define DDGI_GI_SHADOW_DIRECT_GLSL

#include "common/lights.glsl"
#include "gi/shadow_rays.glsl"
#include "shared/frame_data.h"
#ifdef DDGI_SHADOW_FIELD_SET
#include "gi/shadow_field.glsl"
#else
// No shadow field bound in this kernel: a sample that is never taken.
#include "shared/shadow_field_data.h"
struct ShadowSample {
  vec4 visibility[kShadowMaxGroups];
  float ao;
  float weight_sum;
};
float shadow_sample_light(ShadowSample s, uint light) { return 1.0; }
#endif

// Mean visibility of one light over `samples` points on it (one for point lights).
float traced_visibility(vec3 p, vec3 n, GpuLight light, uint samples, inout Rng rng) {
  const uint count = light.radius > 0.0 ? max(samples, 1u) : 1u;
  float sum = 0.0;
  for (uint s = 0u; s < count; ++s) {
    const vec2 jitter = vec2((float(s) + rng_next(rng)) / float(count), rng_next(rng));
    sum += shadow_ray_visibility(p, n, light, jitter);
  }
  return sum / float(count);
}

// Lambertian reflected radiance from every light (and, in the AO mode with `add_sky`, from the
// sky through the field's ambient occlusion). `samples`: shadow rays per spherical light in the
// traced mode. `to_viewer`: unit, towards whoever sees the surface (biases the field lookup).
vec3 direct_light(Surface s, uint mode, uint samples, vec3 to_viewer, bool add_sky,
                  inout Rng rng) {
  // The two original modes, exactly as before (the path tracer's NEE shares them).
  if (mode == kDirectUnshadowed) return direct_lighting(s, false, rng);
  if (mode == kDirectTracedShadows && samples <= 1u) return direct_lighting(s, true, rng);

  // With no punctual light the shadow-field mode has nothing to shadow: no field lookup (the AO
  // mode still reads the field for the sky's occlusion).
  bool from_field = (mode == kDirectShadowField && scene.light_count > 0u) ||
                    mode == kDirectAmbientOcclusion;
  uint kept = 0u;
  bool overflow_traced = true;
  ShadowSample shadowing;
  shadowing.ao = 1.0;
#ifdef DDGI_SHADOW_FIELD_SET
  if (from_field) {
    shadowing = sample_shadow_field(s.position, s.normal, to_viewer);
    kept = shadow.light_count;
    overflow_traced = (shadow.flags & kShadowOverflowTraced) != 0u;
  }
#else
  from_field = false;  // every light gets traced shadow rays
#endif

  vec3 sum = vec3(0.0);
  for (uint i = 0u; i < scene.light_count; ++i) {
    const GpuLight light = scene_lights[i];
    // The field's visibility already averages the light's disc: shade from its centre.
    const LightSample ls = sample_light(light, s.position, vec2(0.0));
    const float cos_theta = dot(s.normal, ls.direction);
    if (cos_theta <= 0.0 || dot(s.geometric_normal, ls.direction) <= 0.0) continue;
    if (all(equal(ls.irradiance, vec3(0.0)))) continue;
    float visibility = 1.0;
    if (from_field && i < kept) {
      visibility = shadow_sample_light(shadowing, i);
    } else if (!from_field || overflow_traced) {
      visibility = traced_visibility(s.position, s.geometric_normal, light,
                                     from_field ? 1u : samples, rng);
    }
    sum += ls.irradiance * cos_theta * visibility;
  }
  vec3 result = sum * s.albedo * kInvPi;
  if (from_field && mode == kDirectAmbientOcclusion && add_sky) {
    // The sky's cosine-weighted mean radiance, exact for a constant colour; a map is read along
    // the normal. Reflected: albedo x open fraction x that mean (see field_data.h's convention).
    result += s.albedo * shadowing.ao * environment_radiance(s.normal);
  }
  return sanitize_radiance(result);
}

#endif
