// The shadow field (set DDGI_SHADOW_FIELD_SET): probe addressing, ray directions, atlas lookups
// and the 8-probe cage query that turns the probes' visibility maps into a soft visibility per
// light at any shading point (docs/shadow-field.md; thesis ch. 5).
#ifndef DDGI_GI_SHADOW_FIELD_GLSL
#define DDGI_GI_SHADOW_FIELD_GLSL

#extension GL_EXT_scalar_block_layout : require

#ifndef DDGI_SHADOW_FIELD_SET
#error "define DDGI_SHADOW_FIELD_SET (the descriptor set the shadow field is bound to)"
#endif

#include "common/math.glsl"
#include "shared/shadow_field_data.h"

layout(set = DDGI_SHADOW_FIELD_SET, binding = kShadowBindingConstants, scalar) readonly buffer
    ShadowFieldBlock {
  ShadowFieldConstants shadow;
};
layout(set = DDGI_SHADOW_FIELD_SET,
       binding = kShadowBindingVisibility) uniform sampler2D shadow_visibility_atlas;
layout(set = DDGI_SHADOW_FIELD_SET,
       binding = kShadowBindingMoments) uniform sampler2D shadow_moments_atlas;

// --- Probes: p = x + counts.x * (y + counts.y * z) ----------------------------------------
ivec3 shadow_probe_coord(uint p) {
  const uint x = p % uint(shadow.counts.x);
  const uint yz = p / uint(shadow.counts.x);
  return ivec3(int(x), int(yz % uint(shadow.counts.y)), int(yz / uint(shadow.counts.y)));
}

uint shadow_probe_index(ivec3 c) {
  return uint(c.x) + uint(shadow.counts.x) * (uint(c.y) + uint(shadow.counts.y) * uint(c.z));
}

vec3 shadow_probe_position(uint p) {
  return shadow.origin + shadow.spacing * vec3(shadow_probe_coord(p));
}

// Ray r of every probe: point r of the spherical Fibonacci set (thesis eq. 4.2-4.3), turned by
// this update's rotation so that successive updates see different directions.
vec3 shadow_ray_direction(uint r) {
  const float kGoldenRatio = 1.61803398875;
  const float n = float(shadow.rays_per_probe);
  const float phi = 2.0 * kPi * fract(float(r) / kGoldenRatio);
  const float z = 1.0 - (2.0 * float(r) + 1.0) / n;
  const float s = sqrt(clamp(1.0 - z * z, 0.0, 1.0));
  return normalize(mat3(shadow.ray_rotation) * vec3(cos(phi) * s, sin(phi) * s, z));
}

// --- Atlases --------------------------------------------------------------------------------
uint shadow_tile_side() { return shadow.texels + 2u * kShadowAtlasBorder; }

// First interior texel of probe p's map in light group `group` (group 0 is also the moments
// atlas layout).
ivec2 shadow_map_origin(uint p, uint group) {
  const uint tile = shadow_tile_side();
  const uvec2 t = uvec2(p % shadow.tiles_per_row, p / shadow.tiles_per_row + group * shadow.tile_rows);
  return ivec2(t * tile + kShadowAtlasBorder);
}

vec3 shadow_texel_direction(uvec2 ij) {
  return octahedral_decode((vec2(ij) + 0.5) / float(shadow.texels) * 2.0 - 1.0);
}

vec2 shadow_atlas_uv(uint p, vec3 d, uint group) {
  const vec2 oct = octahedral_encode(d) * 0.5 + 0.5;
  return (vec2(shadow_map_origin(p, group)) + oct * float(shadow.texels)) / shadow.atlas_size;
}

// --- The cage query -----------------------------------------------------------------------
struct ShadowSample {
  vec4 visibility[kShadowMaxGroups];  // per kept light, sharpened
  float ao;                           // cosine-weighted fraction of open sky
  float weight_sum;                   // 0: no probe answered (visibility and AO are then 1)
};

// Soft visibility of every kept light at surface point `p` with normal `n`, seen from
// `to_viewer` (unit, towards the camera or the probe that looks at p).
ShadowSample sample_shadow_field(vec3 p, vec3 n, vec3 to_viewer) {
  const float min_spacing = min(shadow.spacing.x, min(shadow.spacing.y, shadow.spacing.z));
  // Thesis eq. 4.11: move off the surface so its own Chebyshev test passes.
  const vec3 biased = p + (n * shadow.normal_bias + to_viewer * shadow.view_bias) * min_spacing;
  const ivec3 last = shadow.counts - 1;
  const vec3 grid = (biased - shadow.origin) / shadow.spacing;
  const ivec3 base = clamp(ivec3(floor(grid)), ivec3(0), max(last - 1, ivec3(0)));
  const vec3 alpha = clamp(grid - vec3(base), 0.0, 1.0);
  const bool cosine = (shadow.flags & kShadowCosineWeights) != 0u;

  // Sums weighted by the chosen weighting, and by wrap weights as the fallback when every
  // probe of the cage lies behind the surface (cosine weights are then all zero).
  vec4 vis[kShadowMaxGroups];
  vec4 vis_wrap[kShadowMaxGroups];
  for (uint g = 0u; g < kShadowMaxGroups; ++g) {
    vis[g] = vec4(0.0);
    vis_wrap[g] = vec4(0.0);
  }
  float ao = 0.0, ao_wrap = 0.0, weight_sum = 0.0, wrap_sum = 0.0;
  const uint groups = (shadow.light_count + kShadowLightsPerGroup - 1u) / kShadowLightsPerGroup;
  for (uint i = 0u; i < 8u; ++i) {
    const ivec3 offset = ivec3(i & 1u, (i >> 1) & 1u, (i >> 2) & 1u);
    const uint probe = shadow_probe_index(min(base + offset, last));
    const vec3 probe_pos = shadow_probe_position(probe);
    const vec3 tri = mix(1.0 - alpha, alpha, vec3(offset));
    const float trilinear = max(tri.x * tri.y * tri.z, 0.0);

    // Direction weights (thesis Fig. 5.3): cosine keeps probes behind the surface out.
    const float c = dot(safe_normalize(probe_pos - p, n), n);
    const float wrap = (c + 1.0) * 0.5;

    // Does the probe see the biased point? Chebyshev's bound from its distance moments.
    const vec3 probe_to_point = biased - probe_pos;
    const float r = length(probe_to_point);
    const vec3 dir = safe_normalize(probe_to_point, n);
    const vec4 moments = textureLod(shadow_moments_atlas, shadow_atlas_uv(probe, dir, 0u), 0.0);
    float visible = 1.0;
    if (r > moments.x) {
      const float variance = abs(moments.y - moments.x * moments.x);
      const float d = r - moments.x;
      const float chebyshev = variance / max(variance + d * d, 1e-30);
      visible = chebyshev * chebyshev * chebyshev;
    }

    float w[2];
    w[0] = (cosine ? max(c, 0.0) : wrap * wrap) * visible;
    w[1] = wrap * wrap * visible;
    for (uint k = 0u; k < 2u; ++k) {
      // Crush tiny weights: what a barely visible probe says is mostly a leak.
      float weight = max(w[k], 1e-6);
      const float crush = shadow.weight_crush_threshold;
      if (weight < crush) weight *= weight * weight / (crush * crush);
      w[k] = weight * trilinear;
    }
    // Cosine weights of probes in or behind the surface's plane are exactly zero.
    if (cosine && c <= 0.0) w[0] = 0.0;

    for (uint g = 0u; g < groups; ++g) {
      const vec4 v = textureLod(shadow_visibility_atlas, shadow_atlas_uv(probe, dir, g), 0.0);
      vis[g] += w[0] * v;
      vis_wrap[g] += w[1] * v;
    }
    ao += w[0] * moments.z;
    ao_wrap += w[1] * moments.z;
    weight_sum += w[0];
    wrap_sum += w[1];
  }

  ShadowSample result;
  result.weight_sum = weight_sum > 0.0 ? weight_sum : wrap_sum;
  const float inv = result.weight_sum > 0.0 ? 1.0 / result.weight_sum : 0.0;
  const bool fallback = !(weight_sum > 0.0);
  for (uint g = 0u; g < kShadowMaxGroups; ++g) {
    vec4 v = vec4(1.0);
    if (g < groups && result.weight_sum > 0.0) v = (fallback ? vis_wrap[g] : vis[g]) * inv;
    result.visibility[g] = pow(clamp(v, 0.0, 1.0), vec4(shadow.sharpening));
  }
  result.ao = result.weight_sum > 0.0 ? clamp((fallback ? ao_wrap : ao) * inv, 0.0, 1.0) : 1.0;
  return result;
}

// Visibility of kept light `light` (< shadow.light_count) from a sample.
float shadow_sample_light(ShadowSample s, uint light) {
  return s.visibility[light / kShadowLightsPerGroup][light % kShadowLightsPerGroup];
}

#endif
