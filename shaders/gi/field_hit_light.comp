#version 460
#extension GL_GOOGLE_include_directive : require
// Fused field update, pass 2 (between the trace and the blend): adds to each lit front-face
// hit's radiance the light arriving there from the previous field (DDGI's feedback, one bounce
// per update), weighted as the trace recorded it (ProbeRayHit). The query is the cage query
// every pixel uses; run here, as a compute pass, instead of inside the ray-tracing kernel, it
// neither holds the traversal's registers nor makes it wait on the atlases
// (docs/results/field-at-ray-cost.md measures both forms). The hit point is the probe's
// position plus the hit distance along the ray's direction, as the trace found it.
#include "common/field_update.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) buffer Rays {
  ProbeRay rays[];
};
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingHits, scalar) readonly buffer Hits {
  ProbeRayHit hits[];
};

// Invocation i takes ray i / probes of probe list entry i % probes (ray-major, unlike the
// other field passes): neighbouring invocations light the hits of one ray direction from
// neighbouring probes, which lie close together and read the same probes and atlas texels.
bool hit_light_item(out uint probe, out uint local) {
  const uint id = linear_invocation(pc.row_width);
  probe = 0u;
  local = 0u;
  if (id >= pc.count) return false;
  const uint probes = pc.count / pc.per_probe;
  uint list_index;
  probe = window_probe(id % probes, list_index);
  local = id / probes;
  return probe_lit_this_update(probe, list_index);
}

void main() {
  uint probe, local;
  if (!hit_light_item(probe, local)) return;
  const uint r = pc.first_ray + local;
  if (r < field.fixed_rays) return;  // not lit
  const uint index = probe * rays_per_probe_total() + r;
  const ProbeRay ray = rays[index];
  // Misses and back faces carry what the trace gave them.
  if (ray_missed(ray.distance) || ray_hit_back_face(ray.distance)) return;
  const ProbeRayHit hit = hits[index];
  if (all(equal(hit.weight, vec3(0.0)))) return;
  const vec3 direction = probe_ray_direction(r);
  const vec3 position = probe_position(probe) + ray_distance(ray.distance) * direction;
  const vec3 arriving = sample_irradiance(position, unpack_normal(hit.normal_oct), -direction);
  rays[index].radiance = sanitize_radiance(ray.radiance + hit.weight * arriving);
}
