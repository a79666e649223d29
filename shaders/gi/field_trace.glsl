#version 460
#extension GL_GOOGLE_include_directive : require
// Field update, pass 1 (fused): every probe ray is traced and, when it is one of the blended
// rays, lit where it lands, in one invocation (as RTXGI's probe-trace ray generation does): the
// radiance it carries back (environment on a miss, nothing from back faces: 2021 paper, sec.
// 4.1), times the thin glass it crossed, and its hit distance, into a 16-byte ProbeRay. A
// front-face hit's own light is complete here; the light arriving there from the previous
// field is added by the next pass (field_hit_light.comp, from the 16-byte ProbeRayHit written
// here), or, with probe_bounces > 0 (DDGI_PROBE_PATHS), by the path traced on from the hit here.
// Probe management traces the fixed rays with the same kernel (not lit: only their distances
// count).
#include "common/trace.glsl"
#include "gi/probe_ray_radiance.glsl"

layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) writeonly buffer Rays {
  ProbeRay rays[];
};
#ifndef DDGI_PROBE_PATHS
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingHits, scalar) writeonly buffer Hits {
  ProbeRayHit hits[];
};
#endif

void main() {
  uint probe, local;
  if (!field_lit_item(probe, local)) return;
  const uint r = pc.first_ray + local;
  const uint index = probe * rays_per_probe_total() + r;
  const vec3 origin = probe_position(probe);
  const vec3 direction = probe_ray_direction(r);
  const bool lit = r >= field.fixed_rays;
  // Back faces are never culled: relocation and classification count them. Fixed rays start a
  // hair behind the probe: a probe lying exactly in a surface's plane never hits that surface
  // from its own position, so it would be neither moved off it nor switched Off; starting
  // behind, it sees the surface at distance ~0, a front face one way and a back face the other,
  // and relocation lifts it off (or classification turns it Off).
  const float min_spacing = min(field_grid.spacing.x, min(field_grid.spacing.y, field_grid.spacing.z));
  const float behind = lit ? 0.0 : 1e-3 * min_spacing;
  const Hit hit =
      trace_closest(origin - behind * direction, direction, 0.0, field.max_ray_distance + behind);

  ProbeRay ray;
  ray.radiance = vec3(0.0);
  if (hit.t < 0.0) {
    ray.distance = encode_ray_distance(false, false, 0.0);
    if (lit) ray.radiance = environment_radiance(direction) * hit.transmittance;
  } else {
    const Surface s = surface_at(hit, direction);
    ray.distance = encode_ray_distance(true, s.front_face, max(hit.t - behind, 0.0));
    if (lit && s.front_face) {
#ifdef DDGI_PROBE_PATHS
      ray.radiance = probe_hit_radiance(s, direction, index) * hit.transmittance;
#else
      // The previous field's light at the hit is added by the hit-light pass.
      Rng rng;
      ray.radiance = probe_hit_own_light(s, direction, index, rng) * hit.transmittance;
      hits[index] = ProbeRayHit(probe_hit_arriving_weight(s) * hit.transmittance,
                                pack_normal(s.normal));
#endif
    }
  }
  ray.radiance = sanitize_radiance(ray.radiance);
  rays[index] = ray;
}
