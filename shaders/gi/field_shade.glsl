#version 460
#extension GL_GOOGLE_include_directive : require
// Field update, pass 2: the radiance each blended ray carries back to its probe: emission,
// direct light at the hit, and the previous field's irradiance times albedo (multiple
// bounces). Back faces carry nothing (2021 paper, sec. 4.1); misses carry the environment.
#include "gi/shadow_direct.glsl"
#include "common/field_update.glsl"
#include "common/emitter_direct.glsl"
#include "shared/frame_data.h"

layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) buffer Rays { ProbeRay rays[]; };

void main() {
  uint probe, local;
  if (!field_item(probe, local)) return;
  const uint r = field.fixed_rays + local;
  const uint index = probe * rays_per_probe_total() + r;
  const ProbeRay ray = rays[index];
  const vec3 origin = probe_position(probe);
  const vec3 direction = probe_ray_direction(r);

  vec3 radiance = vec3(0.0);
  if ((ray.flags & kRayHit) == 0u) {
    radiance = environment_radiance(direction);
  } else if ((ray.flags & kRayFrontFace) != 0u) {
    Surface s;
    s.position = ray.position;
    s.normal = unpack_normal(ray.normal_oct);
    s.geometric_normal = unpack_normal(ray.geometric_normal_oct);
    s.albedo = ray.albedo;
    s.emission = ray.emission;
    s.front_face = true;
    Rng rng = rng_seed(index, field.update_index, 0x5bd1e995u);
    // Compiled twice: with DDGI_SHADOW_FIELD_SET the shadow field's modes read it here too;
    // without, they shade probe-ray hits with traced shadow rays.
    const vec3 direct = direct_light(s, field.direct_mode, 1u, -direction, false, rng);
    const vec3 indirect = s.albedo * field.energy_conservation *
                          sample_irradiance(s.position, s.normal, -direction);
    if (field.emitter_samples > 0u) {
      // Emitter light reaches surfaces by sampling (here and per pixel), not through the field:
      // what probes see of an emitter would count it twice.
      radiance = direct + emitter_direct(s, field.emitter_samples, rng) + indirect;
    } else {
      radiance = s.emission + direct + indirect;
    }
  }
  const float t = (ray.flags & kRayHit) != 0u ? ray.distance : field.max_ray_distance;
  radiance *= glass_transmittance(origin, direction, 0.0, t);
  rays[index].radiance = sanitize_radiance(radiance);
}
