// A path's light, shared by the irradiance field's probe rays (gi/probe_ray_radiance.glsl) and
// the frame's paths per pixel (render/pixel_paths.glsl): a vertex's own light, the previous
// field's light at a vertex, and the cosine-weighted light arriving at a surface estimated by
// one path that reads the field where it ends. Needs the field (set kFieldSet) and the scene.
#ifndef DDGI_GI_FIELD_PATHS_GLSL
#define DDGI_GI_FIELD_PATHS_GLSL

#include "gi/shadow_direct.glsl"
#include "common/field.glsl"
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
// at a probe-ray hit, and at the last vertex of a path.
vec3 field_light_at(Surface s, vec3 direction) {
  return probe_hit_arriving_weight(s) * sample_irradiance(s.position, s.normal, -direction);
}

// Cosine-weighted mean radiance (M) arriving at `s` estimated by one path of at most `vertices`
// further vertices: at each, its own light (vertex_light) plus albedo times the next. Russian
// roulette after the fourth vertex keeps it unbiased below the cap; a path that reaches the cap
// reads the previous field there for the light of every later bounce (DDGI's feedback, past the
// traced vertices), so a short path does not cut that light off. Only the kernels that call it
// compile its traversal (a second traversal inlined in every probe-ray kernel more than doubled
// their compile time on lavapipe).
vec3 traced_irradiance(Surface s, uint vertices, inout Rng rng) {
  vec3 sum = vec3(0.0), throughput = vec3(1.0);
  for (uint bounce = 0u; bounce < vertices; ++bounce) {
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
    if (bounce + 1u == vertices) {
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
