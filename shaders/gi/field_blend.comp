#version 460
#extension GL_GOOGLE_include_directive : require
// Fused field update, pass 2: one workgroup per probe blends both of its maps and writes their
// borders. The probe's rays are loaded into shared memory once per chunk (each ray's direction
// computed and its distance processed once, not once per texel); every texel of both maps then
// sums them from there in ray order, as the split per-texel kernels do, so both give the same
// texels. The borders are copied by the same workgroup once its texels are stored.
#include "gi/field_blend.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) readonly buffer Rays {
  ProbeRay rays[];
};

const uint kRayChunk = 256u;  // 7 KiB of shared memory
shared vec3 chunk_direction[kRayChunk];
shared vec3 chunk_radiance[kRayChunk];
shared float chunk_distance[kRayChunk];

// Loads rays [start, start + kRayChunk) of the probe whose rays begin at `first`.
void load_chunk(uint first, uint start) {
  const uint count = min(kRayChunk, field.rays_per_probe - start);
  for (uint i = gl_LocalInvocationIndex; i < count; i += gl_WorkGroupSize.x) {
    const ProbeRay ray = rays[first + start + i];
    chunk_direction[i] = probe_ray_direction(field.fixed_rays + start + i);
    chunk_radiance[i] = ray.radiance;
    chunk_distance[i] = blended_ray_distance(ray.distance);
  }
}

// Adds the loaded chunk's rays to an irradiance texel's (xyz: sum, w: weight) or a distance
// texel's (xy: sum, w: weight) running sums.
vec4 sum_chunk(uint count, vec3 texel_direction, bool irradiance, vec4 sums) {
  for (uint i = 0u; i < count; ++i) {
    const float c = dot(texel_direction, chunk_direction[i]);
    if (irradiance) {
      const float w = max(0.0, c);
      if (w > 0.0) sums += vec4(w * chunk_radiance[i], w);
    } else if (c > 0.0) {
      const float w = pow(c, field.distance_exponent);
      const float d = chunk_distance[i];
      sums += vec4(w * d, w * d * d, 0.0, w);
    }
  }
  return sums;
}

void main() {
  // One workgroup per probe of the window; rows of workgroups when the window is long.
  const uint slot = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
  if (slot >= pc.count) return;  // the whole workgroup
  const uint probe = probe_list[(pc.list_start + slot) % pc.list_size];
  const bool reset = (probe_states[probe].flags & kProbeResetHistory) != 0u;
  const uint first = probe * rays_per_probe_total() + field.fixed_rays;
  const uint n = field.rays_per_probe;
  const uint ni = field.irradiance_texels, nd = field.distance_texels;
  const uint texels = ni * ni + nd * nd;  // irradiance texels first, then distance texels

  for (uint base = 0u; base < texels; base += gl_WorkGroupSize.x) {
    const uint t = base + gl_LocalInvocationIndex;
    const bool irradiance = t < ni * ni;
    const uint side = irradiance ? ni : nd;
    const uint k = irradiance ? t : t - ni * ni;
    const uvec2 ij = uvec2(k % side, k / side);
    const vec3 texel_direction = octahedral_texel_direction(ij, side);
    vec4 sums = vec4(0.0);
    for (uint start = 0u; start < n; start += kRayChunk) {
      // All rays fit one chunk (the common case): it is loaded for the first texels only.
      if (n > kRayChunk || base == 0u) {
        barrier();  // the previous chunk's readers are done
        load_chunk(first, start);
        barrier();
      }
      if (t < texels) sums = sum_chunk(min(kRayChunk, n - start), texel_direction, irradiance, sums);
    }
    if (t < texels) {
      if (irradiance) {
        blend_irradiance_texel(probe, ij, sums.xyz, sums.w, reset);
      } else {
        blend_distance_texel(probe, ij, sums.xy, sums.w, reset);
      }
    }
  }

  memoryBarrierImage();
  barrier();  // every texel of both maps is stored
  const uint borders = 4u * (max(ni, nd) + 1u);
  for (uint b = gl_LocalInvocationIndex; b < borders; b += gl_WorkGroupSize.x) {
    copy_border_texel(probe, b);
  }
  if (gl_LocalInvocationIndex == 0u) probe_states[probe].flags &= ~kProbeResetHistory;
}
