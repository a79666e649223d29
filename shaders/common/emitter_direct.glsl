// Direct light from emissive triangles by next-event estimation: an emitter triangle picked by
// area x luminance, a direction in the solid angle it subtends (shaders/common/emitters.glsl),
// a shadow ray each. The option the irradiance field is measured against: with it on, emitter
// light reaches surfaces directly instead of through probe rays that hit the emitters
// (IrradianceFieldParams::emitter_sampling).
#ifndef DDGI_COMMON_EMITTER_DIRECT_GLSL
#define DDGI_COMMON_EMITTER_DIRECT_GLSL

#include "common/emitters.glsl"
#include "common/trace.glsl"

// Lambertian reflected radiance at `s` from every emitter, averaged over `samples` samples.
vec3 emitter_direct(Surface s, uint samples, inout Rng rng) {
  if (scene.emitter_count == 0u || samples == 0u) return vec3(0.0);
  const vec3 origin = offset_ray_origin(s.position, s.geometric_normal);
  vec3 sum = vec3(0.0);
  for (uint i = 0u; i < samples; ++i) {
    const float u = rng_next(rng);
    const vec2 uv = vec2(rng_next(rng), rng_next(rng));
    const EmitterDirection e = sample_emitter_direction(s.position, u, uv);
    if (all(equal(e.weight, vec3(0.0)))) continue;
    const vec3 to_emitter = e.position - origin;
    const float d2 = dot(to_emitter, to_emitter);
    if (!(d2 > 0.0)) continue;
    const float d = sqrt(d2);
    const vec3 l = to_emitter / d;
    const float cos_receiver = dot(s.normal, l);
    if (cos_receiver <= 0.0 || dot(s.geometric_normal, l) <= 0.0) continue;
    // Stop short of the emitter so its own surface does not count as an occluder.
    const vec3 visibility = trace_transmittance(origin, l, 0.0, d * (1.0 - 1e-4));
    // Radiance x cos over the direction's solid-angle density.
    sum += e.weight * visibility * cos_receiver;
  }
  return sanitize_radiance(sum / float(samples) * s.albedo * kInvPi);
}

#endif
