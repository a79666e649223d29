#version 460
#extension GL_GOOGLE_include_directive : require
// Fused field update, pass 2: one workgroup per probe blends both of its maps and writes their
// borders. The probe's rays are loaded into shared memory once per chunk (each ray's direction
// computed and its distance processed once, not once per texel), packed so that one ray is two
// 16-byte broadcast reads; each invocation sums them for one irradiance texel and one distance
// texel at once, in ray order as the split per-texel kernels do, so both give the same texels.
// Each invocation also writes the border texels that copy its own: no borders pass, no barrier.
// An adaptive update (docs/adaptive-rays.md) skips the probes it leaves settled, as the trace
// did, and sets each blended probe's heat from how far its irradiance moved (blended_flags).
#include "gi/field_blend.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) readonly buffer Rays {
  ProbeRay rays[];
};

// 64 rays (2 KiB): with 256 the compiler gave the blend 255 registers (four workgroups to an SM);
// with 64 it takes 80 and the blend ran in 0.59-0.77 of the time on an H100
// (docs/results/field-at-ray-cost.md), the extra loads and barriers included.
const uint kRayChunk = 64u;
shared vec4 chunk_direction_distance[kRayChunk];  // xyz: direction, w: distance as blended
shared vec4 chunk_radiance[kRayChunk];            // xyz: radiance towards the probe
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingDrift, scalar) buffer Drifts {
  // The largest luminance sum (over its texels) of a probe's history since the field started,
  // as float bits (non-negative floats order as their bits do: atomicMax).
  uint brightest_bits;
  uint pad0, pad1, pad2;
  ProbeDrift drifts[];
};

// Adaptive rays: the probe's irradiance as this update estimates it and as its history holds
// it, in low orders (x: mean luminance over the texels, yzw: luminance-weighted mean direction),
// summed per invocation, then over the workgroup by its first invocation (the workgroup is
// IrradianceField's kProbeWorkgroup, 64 invocations).
const uint kMaxInvocations = 64u;
shared vec4 fresh_moments[kMaxInvocations];
shared vec4 old_moments[kMaxInvocations];

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

// One ray's share of an irradiance texel's and a distance texel's sums.
void add_irradiance_ray(uint i, vec3 texel_direction, inout TexelSums sums) {
  const float w = max(0.0, dot(texel_direction, chunk_direction_distance[i].xyz));
  sums.irradiance += vec4(w * chunk_radiance[i].xyz, w);
}

void add_distance_ray(uint i, vec3 texel_direction, inout TexelSums sums) {
  const vec4 ray = chunk_direction_distance[i];
  const float w = pow(max(0.0, dot(texel_direction, ray.xyz)), field.distance_exponent);
  sums.distance += vec3(w * ray.w, w * ray.w * ray.w, w);
}

// Adds the loaded chunk's first `count` rays to the sums of the irradiance texel facing
// `irradiance_direction` and the distance texel facing `distance_direction` (each only where
// this invocation has one: the distance map has more texels by default). Rays outside a
// texel's hemisphere add exact zeros (no branch per ray): the sums equal the split kernels'.
// Which texels an invocation has is decided once, outside the ray loops.
TexelSums sum_chunk(uint count, bool irradiance, vec3 irradiance_direction, bool distance,
                    vec3 distance_direction, TexelSums sums) {
  if (irradiance && distance) {
    for (uint i = 0u; i < count; ++i) {
      add_irradiance_ray(i, irradiance_direction, sums);
      add_distance_ray(i, distance_direction, sums);
    }
  } else if (irradiance) {
    for (uint i = 0u; i < count; ++i) add_irradiance_ray(i, irradiance_direction, sums);
  } else if (distance) {
    for (uint i = 0u; i < count; ++i) add_distance_ray(i, distance_direction, sums);
  }
  return sums;
}

// How far this update's estimate of the probe lies from its history, signed, relative to their
// size, or to kDriftFloor of the brightest probe's where that is larger (changes of light far
// too dim to see do not count): the low orders of all its rays together.
vec4 probe_change() {
  vec4 fresh = vec4(0.0), old = vec4(0.0);
  for (uint i = 0u; i < min(gl_WorkGroupSize.x, kMaxInvocations); ++i) {
    fresh += fresh_moments[i];
    old += old_moments[i];
  }
  atomicMax(brightest_bits, floatBitsToUint(old.x));
  const float floor = kDriftFloor * 2.0 * uintBitsToFloat(brightest_bits);
  return (fresh - old) / max(fresh.x + old.x, max(floor, 1e-30));
}

float change_size(vec4 change) { return abs(change.x) + length(change.yzw); }

// The probe's flags after its blend: history valid and, in an adaptive update, its heat: full
// when it has just started or its drift (its changes averaged over the last updates, where
// noise cancels and a history still catching up does not) is a gap (field_data.h), else one
// less than it was.
uint blended_flags(uint probe, uint flags, bool reset) {
  flags &= ~kProbeResetHistory;
  if (pc.skip_settled == 0u) return flags;
  ProbeDrift seen = drifts[probe];
  if (reset) {
    seen.drift = vec4(0.0);
    seen.usual = 0.0;
  } else {
    const vec4 change = probe_change();
    seen.drift = mix(seen.drift, change, kDriftWeight);
    seen.usual = mix(seen.usual, change_size(change), kUsualWeight);
  }
  drifts[probe] = seen;
  const uint heat = (flags & kProbeHeatMask) >> kProbeHeatShift;
  const float drift = change_size(seen.drift);
  const bool changing =
      reset || (drift > field.settle_threshold && drift > kDriftOverUsual * seen.usual);
  const uint next = changing ? field.hot_updates : (heat > 0u ? heat - 1u : 0u);
  return (flags & ~kProbeHeatMask) | (min(next, 0xFFu) << kProbeHeatShift);
}

void main() {
  // One workgroup per probe of the window; rows of workgroups when the window is long.
  const uint slot = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
  if (slot >= pc.count) return;  // the whole workgroup
  const uint list_index = (pc.list_start + slot) % pc.list_size;
  const uint probe = probe_list[list_index];
  if (!probe_lit_this_update(probe, list_index)) return;  // the whole workgroup, as the trace
  select_probe_volume(probe);
  const uint flags = probe_states[probe].flags;
  const bool reset = (flags & kProbeResetHistory) != 0u;
  const bool adaptive = pc.skip_settled != 0u;
  const uint first = probe * rays_per_probe_total() + field.fixed_rays;
  const uint n = field.rays_per_probe;
  const uint ni = field.irradiance_texels, nd = field.distance_texels;
  vec4 fresh_sum = vec4(0.0), old_sum = vec4(0.0);  // adaptive rays: this invocation's texels

  // Invocation t of a round takes irradiance texel t and distance texel t (where they exist).
  for (uint base = 0u; base < max(ni * ni, nd * nd); base += gl_WorkGroupSize.x) {
    const uint t = base + gl_LocalInvocationIndex;
    const bool irradiance = t < ni * ni, distance = t < nd * nd;
    const uvec2 irradiance_ij = uvec2(t % ni, t / ni);
    const uvec2 distance_ij = uvec2(t % nd, t / nd);
    const vec3 irradiance_direction = octahedral_texel_direction(irradiance_ij, ni);
    const vec3 distance_direction = octahedral_texel_direction(distance_ij, nd);
    const vec4 irradiance_old = irradiance ? irradiance_history(probe, irradiance_ij) : vec4(0.0);
    const vec4 distance_old = distance ? distance_history(probe, distance_ij) : vec4(0.0);
    TexelSums sums = TexelSums(vec4(0.0), vec3(0.0));
    for (uint start = 0u; start < n; start += kRayChunk) {
      // A probe whose rays fit one chunk loads it for the first round only.
      if (n > kRayChunk || base == 0u) {
        barrier();  // the previous chunk's readers are done
        load_chunk(first, start);
        barrier();
      }
      sums = sum_chunk(min(kRayChunk, n - start), irradiance, irradiance_direction, distance,
                       distance_direction, sums);
    }
    if (irradiance) {
      vec2 seen;
      const vec4 texel = blend_irradiance_texel(probe, irradiance_ij, irradiance_old,
                                                sums.irradiance.xyz, sums.irradiance.w, reset,
                                                adaptive, seen);
      store_irradiance_border_copies(probe, irradiance_ij, texel);
      fresh_sum += seen.x * vec4(1.0, irradiance_direction);
      old_sum += seen.y * vec4(1.0, irradiance_direction);
    }
    if (distance) {
      const vec4 texel = blend_distance_texel(probe, distance_ij, distance_old, sums.distance.xy,
                                              sums.distance.z, reset);
      store_distance_border_copies(probe, distance_ij, texel);
    }
  }
  if (adaptive && gl_LocalInvocationIndex < kMaxInvocations) {
    fresh_moments[gl_LocalInvocationIndex] = fresh_sum;
    old_moments[gl_LocalInvocationIndex] = old_sum;
  }
  barrier();  // every invocation's sums are in
  // Every invocation read the flags before this; no other workgroup blends this probe.
  if (gl_LocalInvocationIndex == 0u) {
    probe_states[probe].flags = blended_flags(probe, flags, reset);
  }
}
