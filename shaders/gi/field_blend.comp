#version 460
#extension GL_GOOGLE_include_directive : require
// Fused field update, pass 2: one workgroup per probe blends both of its maps and writes their
// borders. The probe's rays are loaded into shared memory once per chunk (each ray's direction
// computed and its distance processed once, not once per texel), packed so that one ray is two
// 16-byte broadcast reads; each invocation sums them for one irradiance texel and one distance
// texel at once, in ray order as the split per-texel kernels do, so both give the same texels.
// Each invocation also writes the border texels that copy its own: no borders pass, no barrier.
#include "gi/field_blend.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) readonly buffer Rays {
  ProbeRay rays[];
};

const uint kRayChunk = 256u;                // 8 KiB of shared memory
shared vec4 chunk_direction_distance[kRayChunk];  // xyz: direction, w: distance as blended
shared vec4 chunk_radiance[kRayChunk];            // xyz: radiance towards the probe

// Loads rays [start, start + kRayChunk) of the probe whose rays begin at `first`.
void load_chunk(uint first, uint start) {
  const uint count = min(kRayChunk, field.rays_per_probe - start);
  for (uint i = gl_LocalInvocationIndex; i < count; i += gl_WorkGroupSize.x) {
    const ProbeRay ray = rays[first + start + i];
    chunk_direction_distance[i] = vec4(probe_ray_direction(field.fixed_rays + start + i),
                                       blended_ray_distance(ray.distance));
    chunk_radiance[i] = vec4(ray.radiance, 0.0);
  }
}

// One invocation's running sums: irradiance (xyz: cosine-weighted radiance, w: weight) and
// distance (x: weighted distance, y: weighted squared distance, z: weight).
struct TexelSums {
  vec4 irradiance;
  vec3 distance;
};

// Adds the loaded chunk's first `count` rays to the sums of the irradiance texel facing
// `irradiance_direction` and the distance texel facing `distance_direction` (each only where
// this invocation has one: the distance map has more texels by default). Rays outside a
// texel's hemisphere add exact zeros (no branch per ray): the sums equal the split kernels'.
TexelSums sum_chunk(uint count, bool irradiance, vec3 irradiance_direction, bool distance,
                    vec3 distance_direction, TexelSums sums) {
  for (uint i = 0u; i < count; ++i) {
    const vec4 ray = chunk_direction_distance[i];
    if (irradiance) {
      const float w = max(0.0, dot(irradiance_direction, ray.xyz));
      sums.irradiance += vec4(w * chunk_radiance[i].xyz, w);
    }
    if (distance) {
      const float w = pow(max(0.0, dot(distance_direction, ray.xyz)), field.distance_exponent);
      sums.distance += vec3(w * ray.w, w * ray.w * ray.w, w);
    }
  }
  return sums;
}

void main() {
  // One workgroup per probe of the window; rows of workgroups when the window is long.
  const uint slot = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
  if (slot >= pc.count) return;  // the whole workgroup
  const uint probe = probe_list[(pc.list_start + slot) % pc.list_size];
  select_probe_volume(probe);
  const bool reset = (probe_states[probe].flags & kProbeResetHistory) != 0u;
  const uint first = probe * rays_per_probe_total() + field.fixed_rays;
  const uint n = field.rays_per_probe;
  const uint ni = field.irradiance_texels, nd = field.distance_texels;

  // Invocation t of a round takes irradiance texel t and distance texel t (where they exist).
  for (uint base = 0u; base < max(ni * ni, nd * nd); base += gl_WorkGroupSize.x) {
    const uint t = base + gl_LocalInvocationIndex;
    const bool irradiance = t < ni * ni, distance = t < nd * nd;
    const uvec2 irradiance_ij = uvec2(t % ni, t / ni);
    const uvec2 distance_ij = uvec2(t % nd, t / nd);
    const vec3 irradiance_direction = octahedral_texel_direction(irradiance_ij, ni);
    const vec3 distance_direction = octahedral_texel_direction(distance_ij, nd);
    TexelSums sums = TexelSums(vec4(0.0), vec3(0.0));
    for (uint start = 0u; start < n; start += kRayChunk) {
      // All rays fit one chunk (the common case): it is loaded for the first round only.
      if (n > kRayChunk || base == 0u) {
        barrier();  // the previous chunk's readers are done
        load_chunk(first, start);
        barrier();
      }
      sums = sum_chunk(min(kRayChunk, n - start), irradiance, irradiance_direction, distance,
                       distance_direction, sums);
    }
    if (irradiance) {
      const vec4 texel =
          blend_irradiance_texel(probe, irradiance_ij, sums.irradiance.xyz, sums.irradiance.w,
                                 reset);
      store_irradiance_border_copies(probe, irradiance_ij, texel);
    }
    if (distance) {
      const vec4 texel =
          blend_distance_texel(probe, distance_ij, sums.distance.xy, sums.distance.z, reset);
      store_distance_border_copies(probe, distance_ij, texel);
    }
  }
  // Every invocation read the flag before this; no other workgroup blends this probe.
  if (gl_LocalInvocationIndex == 0u) probe_states[probe].flags &= ~kProbeResetHistory;
}
