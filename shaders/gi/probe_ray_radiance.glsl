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

#include "gi/shadow_direct.glsl"
#include "common/field_update.glsl"
#include "common/emitter_direct.glsl"
#include "common/sampling.glsl"

// The light a vertex's own surface adds to the path: emission (unless emitters are sampled) +
// direct light + sampled emitters.
vec3 vertex_light(Surface s, vec3 direction, inout Rng rng) {
  const vec3 direct = direct_light(s, field.direct_mode, 1u, -direction, false, rng);
  if (field.emitter_samples > 0u) return direct + emitter_direct(s, field.emitter_samples, rng);
  return s.emission + direct;
}

// What the light arriving at a hit from the previous field is multiplied by.
vec3 probe_hit_arriving_weight(Surface s) { return s.albedo * field.energy_conservation; }

// The light the previous field sends back from `s`, reached along `direction`: DDGI's feedback
// at a probe-ray hit, and at the last vertex of a probe path.
vec3 field_light_at(Surface s, vec3 direction) {
  return probe_hit_arriving_weight(s) * sample_irradiance(s.position, s.normal, -direction);
}

#ifdef DDGI_PROBE_PATHS
// Cosine-weighted mean radiance (M) arriving at `s` estimated by one path of at most
// field.probe_bounces further vertices: at each, its own light (vertex_light) plus albedo times
// the next. Russian roulette after the fourth vertex keeps it unbiased below the cap; a path
// that reaches the cap reads the previous field there for the light of every later bounce
// (DDGI's feedback, past the traced vertices), so a short path does not cut that light off.
vec3 traced_irradiance(Surface s, inout Rng rng) {
  vec3 sum = vec3(0.0), throughput = vec3(1.0);
  for (uint bounce = 0u; bounce < field.probe_bounces; ++bounce) {
    const vec3 direction =
        sample_cosine_hemisphere(s.normal, vec2(rng_next(rng), rng_next(rng)));
    if (dot(direction, s.geometric_normal) <= 0.0) break;
    const Hit hit = trace_closest(offset_ray_origin(s.position, s.geometric_normal), direction,
                                  0.0, kFloatMax);
    throughput *= hit.transmittance;
    if (hit.t < 0.0) {
      sum += throughput * environment_radiance(direction);
      break;
    }
    s = surface_at(hit, direction);
    if (!s.front_face) break;  // inside geometry: no light
    sum += throughput * vertex_light(s, direction, rng);
    if (bounce + 1u == field.probe_bounces) {
      sum += throughput * field_light_at(s, direction);
      break;
    }
    throughput *= s.albedo;
    if (bounce >= 3u) {
      const float survive = min(max_component(throughput), 1.0);
      if (!(rng_next(rng) < survive)) break;
      throughput /= survive;
    }
  }
  return sum;
}
#endif

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
  return own + s.albedo * traced_irradiance(s, rng);
#else
  return own + field_light_at(s, direction);
#endif
}

#endif
