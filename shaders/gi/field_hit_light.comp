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

// The order the window's entries are lit in: read as a grid of the field's counts (what they
// are when every probe of a volume is traced, in ascending order), each group of four whole
// layers is taken in 4x2x4 blocks, so that a warp's 32 invocations light the hits of one ray
// direction from a block of neighbouring probes rather than a row: the hits, and the probes and
// atlas texels their queries read, lie closer together (docs/results/field-at-ray-cost.md,
// "hit-light order"). Entries past the last whole group, and grids whose rows do not divide into
// blocks, keep the list's order. A permutation of [0, entries) for any list, so only the speed
// depends on what the list holds.
const uvec3 kHitLightBlock = uvec3(4u, 2u, 4u);
uint hit_light_entry(uint entry, uint entries) {
  const uvec3 b = kHitLightBlock;
  const uvec2 n = uvec2(field.counts.xy);
  const uint group = n.x * n.y * b.z;
  if (n.x % b.x != 0u || n.y % b.y != 0u || entry >= entries / group * group) return entry;
  const uint k = entry % group;
  const uint w = k % (b.x * b.y * b.z), block = k / (b.x * b.y * b.z);
  const uint x = (block % (n.x / b.x)) * b.x + w % b.x;
  const uint y = (block / (n.x / b.x)) * b.y + (w / b.x) % b.y;
  const uint z = w / (b.x * b.y);
  return entry - k + x + n.x * (y + n.y * z);
}

// Invocation i takes ray i / probes of window entry hit_light_entry(i % probes) (ray-major,
// unlike the other field passes): neighbouring invocations light the hits of one ray direction
// from neighbouring probes, which lie close together and read the same probes and atlas texels.
bool hit_light_item(out uint probe, out uint local) {
  const uint id = linear_invocation(pc.row_width);
  probe = 0u;
  local = 0u;
  if (id >= pc.count) return false;
  const uint probes = pc.count / pc.per_probe;
  uint list_index;
  probe = window_probe(hit_light_entry(id % probes, probes), list_index);
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
