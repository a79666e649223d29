// The radiance a probe ray's front-face hit sends back to its probe: emission, direct light at
// the hit, and the previous field's irradiance times albedo (multiple bounces). Shared by the
// fused trace (field_trace.glsl) and the split update's shade pass (field_shade.glsl).
// Compiled twice: with DDGI_SHADOW_FIELD_SET the shadow field's modes read it here too;
// without, they shade probe-ray hits with traced shadow rays.
#ifndef DDGI_GI_PROBE_RAY_RADIANCE_GLSL
#define DDGI_GI_PROBE_RAY_RADIANCE_GLSL

#include "gi/shadow_direct.glsl"
#include "common/field_update.glsl"
#include "common/emitter_direct.glsl"

// `index`: the ray's index in the ray buffer (seeds its random numbers).
vec3 probe_hit_radiance(Surface s, vec3 direction, uint index) {
  Rng rng = rng_seed(index, field.update_index, 0x5bd1e995u);
  const vec3 direct = direct_light(s, field.direct_mode, 1u, -direction, false, rng);
  const vec3 indirect = s.albedo * field.energy_conservation *
                        sample_irradiance(s.position, s.normal, -direction);
  if (field.emitter_samples > 0u) {
    // Emitter light reaches surfaces by sampling (here and per pixel), not through the field:
    // what probes see of an emitter would count it twice.
    return direct + emitter_direct(s, field.emitter_samples, rng) + indirect;
  }
  return s.emission + direct + indirect;
}

#endif
