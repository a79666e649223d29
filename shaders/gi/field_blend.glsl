// What every field blend does to one texel once its rays are summed, shared by the fused
// per-probe blend (field_blend.comp) and the split per-texel kernels: the irradiance texel's
// perceptual encoding and per-texel hysteresis (2021 paper, eq. 1, sec. 4.2-4.3) and the distance
// texel's clamped, back-face-shortened moments (thesis eq. 4.14-4.16; 2021 paper, sec. 4.1).
#ifndef DDGI_GI_FIELD_BLEND_GLSL
#define DDGI_GI_FIELD_BLEND_GLSL

#include "common/field_update.glsl"

layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingIrradianceOut, rgba32f) coherent uniform image2D irradiance_out;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingDistanceOut, rg32f) coherent uniform image2D distance_out;

float max_component(vec3 v) { return max(v.x, max(v.y, v.z)); }

// The distance a ray adds to the distance texels: back faces shortened, all clamped to the
// visibility range.
float blended_ray_distance(float encoded) {
  float d = ray_distance(encoded);
  if (!ray_missed(encoded) && ray_hit_back_face(encoded)) d *= field.backface_distance_scale;
  return clamp(d, 0.0, field.max_visibility_distance);
}

ivec2 texel_coord(uint probe, uvec2 ij, uint texels) {
  return ivec2(probe_tile_origin(probe, texels) + kAtlasBorder + ij);
}

// Blends the cosine-weighted radiance `sum` / `weight_sum` into irradiance texel ij.
void blend_irradiance_texel(uint probe, uvec2 ij, vec3 sum, float weight_sum, bool reset) {
  // No ray in this texel's hemisphere this update (very few rays): keep the history.
  if (!(weight_sum > 0.0)) return;
  const ivec2 coord = texel_coord(probe, ij, field.irradiance_texels);
  const vec3 fresh = pow(sanitize_radiance(sum / weight_sum), vec3(1.0 / field.irradiance_gamma));
  const vec3 old = imageLoad(irradiance_out, coord).rgb;

  float hysteresis = field.hysteresis;
  if (reset) {
    hysteresis = 0.0;
  } else {
    // Relative change in the encoded space: the same thresholds at every light intensity.
    const float change = max_component(abs(fresh - old)) /
                         max(max_component(max(fresh, old)), 1e-30);
    if (change > field.change_threshold) hysteresis = max(0.0, hysteresis - 0.15);
    if (change > field.new_distribution_threshold) hysteresis = 0.0;
  }
  imageStore(irradiance_out, coord, vec4(mix(fresh, old, hysteresis), 1.0));
}

// Blends the weighted distance moments `sum` / `weight_sum` into distance texel ij.
void blend_distance_texel(uint probe, uvec2 ij, vec2 sum, float weight_sum, bool reset) {
  if (!(weight_sum > 0.0)) return;
  const ivec2 coord = texel_coord(probe, ij, field.distance_texels);
  const vec2 fresh = sum / weight_sum;
  const vec2 old = imageLoad(distance_out, coord).rg;
  const float hysteresis = reset ? 0.0 : field.distance_hysteresis;
  imageStore(distance_out, coord, vec4(mix(fresh, old, hysteresis), 0.0, 0.0));
}

// Border texel b (0 <= b < 4 * (n + 1)) of an n x n map: where it is and where it copies from,
// both relative to the map's first interior texel. Mirrored along each edge, opposite corners
// at the corners, so bilinear lookups near an edge blend with the texels that are its
// neighbours on the sphere.
void border_texel(uint b, int n, out ivec2 dst, out ivec2 src) {
  const int i = int(b);
  if (i < n) {
    dst = ivec2(i, -1);
    src = ivec2(n - 1 - i, 0);
  } else if (i < 2 * n) {
    dst = ivec2(i - n, n);
    src = ivec2(n - 1 - (i - n), n - 1);
  } else if (i < 3 * n) {
    dst = ivec2(-1, i - 2 * n);
    src = ivec2(0, n - 1 - (i - 2 * n));
  } else if (i < 4 * n) {
    dst = ivec2(n, i - 3 * n);
    src = ivec2(n - 1, n - 1 - (i - 3 * n));
  } else {
    const int corner = i - 4 * n;
    dst = ivec2((corner & 1) == 0 ? -1 : n, corner < 2 ? -1 : n);
    src = ivec2((corner & 1) == 0 ? n - 1 : 0, corner < 2 ? n - 1 : 0);
  }
}

// Copies border texel b of probe's irradiance and distance maps (past either map's border
// count: nothing).
void copy_border_texel(uint probe, uint b) {
  ivec2 dst, src;
  if (b < 4u * (field.irradiance_texels + 1u)) {
    border_texel(b, int(field.irradiance_texels), dst, src);
    const ivec2 base = texel_coord(probe, uvec2(0u), field.irradiance_texels);
    imageStore(irradiance_out, base + dst, imageLoad(irradiance_out, base + src));
  }
  if (b < 4u * (field.distance_texels + 1u)) {
    border_texel(b, int(field.distance_texels), dst, src);
    const ivec2 base = texel_coord(probe, uvec2(0u), field.distance_texels);
    imageStore(distance_out, base + dst, imageLoad(distance_out, base + src));
  }
}

#endif
