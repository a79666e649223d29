// The radiance a probe ray's front-face hit sends back to its probe: emission, direct light at
// the hit, and albedo times the light arriving there: the previous field's irradiance (DDGI's
// feedback, one bounce per update) or, with probe_bounces > 0, a path traced on from the hit
// with next-event estimation at every vertex (DDISH-GI's update; docs/sh-probes.md compares
// them), which reads the previous field where it reaches its last vertex. Shared by the fused
// trace (field_trace.glsl) and the split shade (field_shade.glsl).
// The path form is a kernel variant of its own (DDGI_PROBE_PATHS, built only for fields that
// ask for it): a second traversal inlined in every probe-ray kernel more than doubled their
// compile time on lavapipe.
// Compiled twice: with DDGI_SHADOW_FIELD_SET the shadow field's modes read it here too;
// without, they shade probe-ray hits with traced shadow rays.
#ifndef DDGI_GI_PROBE_RAY_RADIANCE_GLSL
#define DDGI_GI_PROBE_RAY_RADIANCE_GLSL

#include "gi/field_paths.glsl"  // first: it brings the tracing backend's extensions
#include "common/field_update.glsl"

// The light a probe ray's front-face hit adds of its own (emission, direct light, sampled
// emitters). `index`: the ray's index in the ray buffer (seeds its random numbers).
// Emitter light reaches surfaces by sampling (here and per pixel) when emitter_samples > 0,
// not through the field: what probes see of an emitter would count it twice.
vec3 probe_hit_own_light(Surface s, vec3 direction, uint index, out Rng rng) {
  rng = rng_seed(index, field.update_index, 0x5bd1e995u);
  return vertex_light(s, direction, rng);
}

vec3 probe_hit_radiance(Surface s, vec3 direction, uint index) {
  Rng rng;
  const vec3 own = probe_hit_own_light(s, direction, index, rng);
#ifdef DDGI_PROBE_PATHS
  return own + s.albedo * traced_irradiance(s, field.probe_bounces, rng);
#else
  return own + field_light_at(s, direction);
#endif
}

#endif
