// What every field blend does to one texel once its rays are summed, shared by the fused
// per-probe blend (field_blend.comp) and the split per-texel kernels: the irradiance texel's
// perceptual encoding and per-texel hysteresis (2021 paper, eq. 1, sec. 4.2-4.3) and the distance
// texel's clamped, back-face-shortened moments (thesis eq. 4.14-4.16; 2021 paper, sec. 4.1).
#ifndef DDGI_GI_FIELD_BLEND_GLSL
#define DDGI_GI_FIELD_BLEND_GLSL

#include "common/field_update.glsl"

layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingIrradianceOut, rgba32f) uniform image2D irradiance_out;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingDistanceOut, rg32f) uniform image2D distance_out;

float max_component(vec3 v) { return max(v.x, max(v.y, v.z)); }

// The distance a ray adds to the distance texels: back faces shortened, all clamped to the
// visibility range.
float blended_ray_distance(float encoded) {
  float d = ray_distance(encoded);
  if (!ray_missed(encoded) && ray_hit_back_face(encoded)) d *= field.backface_distance_scale;
  return clamp(d, 0.0, field_grid.max_visibility_distance);
}

ivec2 texel_coord(uint probe, uvec2 ij, uint texels) {
  return ivec2(probe_tile_origin(probe, texels) + kAtlasBorder + ij);
}

// Irradiance and distance texel ij of the probe as the previous updates left it. The blends
// load it before they sum the rays, so that its latency passes while they do.
vec4 irradiance_history(uint probe, uvec2 ij) {
  return imageLoad(irradiance_out, texel_coord(probe, ij, field.irradiance_texels));
}

vec4 distance_history(uint probe, uvec2 ij) {
  return imageLoad(distance_out, texel_coord(probe, ij, field.distance_texels));
}

// Blends the cosine-weighted radiance `sum` / `weight_sum` into irradiance texel ij (holding
// `history`); returns the texel as stored (the history, unchanged, when no ray reached its
// hemisphere). `seen`, when `measure` (an adaptive update): this update's estimate and the
// history as linear luminance (what adaptive rays compare, field_blend.comp); zeros otherwise
// and without rays or history.
vec4 blend_irradiance_texel(uint probe, uvec2 ij, vec4 history, vec3 sum, float weight_sum,
                            bool reset, bool measure, out vec2 seen) {
  seen = vec2(0.0);
  // No ray in this texel's hemisphere this update (very few rays): keep the history.
  if (!(weight_sum > 0.0)) return history;
  const vec3 fresh_linear = sanitize_radiance(sum / weight_sum);
  const vec3 fresh = pow(fresh_linear, vec3(1.0 / field.irradiance_gamma));
  const vec3 old = history.rgb;

  float hysteresis = field.hysteresis;
  if (reset) {
    hysteresis = 0.0;
  } else {
    // Relative change in the encoded space: the same thresholds at every light intensity.
    const float change = max_component(abs(fresh - old)) /
                         max(max_component(max(fresh, old)), 1e-30);
    if (change > field.change_threshold) hysteresis = max(0.0, hysteresis - 0.15);
    if (change > field.new_distribution_threshold) hysteresis = 0.0;
    if (measure) {
      const vec3 luminance = vec3(0.2126, 0.7152, 0.0722);
      seen = vec2(dot(luminance, fresh_linear),
                  dot(luminance, pow(old, vec3(field.irradiance_gamma))));
    }
  }
  const vec4 texel = vec4(mix(fresh, old, hysteresis), 1.0);
  imageStore(irradiance_out, texel_coord(probe, ij, field.irradiance_texels), texel);
  return texel;
}

// Blends the weighted distance moments `sum` / `weight_sum` into distance texel ij (holding
// `history`); returns the texel as stored.
vec4 blend_distance_texel(uint probe, uvec2 ij, vec4 history, vec2 sum, float weight_sum,
                          bool reset) {
  if (!(weight_sum > 0.0)) return history;
  const vec2 fresh = sum / weight_sum;
  const float hysteresis = reset ? 0.0 : field.distance_hysteresis;
  const vec4 texel = vec4(mix(fresh, history.rg, hysteresis), 0.0, 0.0);
  imageStore(distance_out, texel_coord(probe, ij, field.distance_texels), texel);
  return texel;
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

// The border texels that copy interior texel ij of an n x n map (border_texel read the other
// way), relative to the map's first interior texel: one per map edge the texel lies on, and
// for a corner texel the opposite border corner. Returns how many (0 to 3).
uint border_copies_of(ivec2 ij, int n, out ivec2 dst[3]) {
  uint count = 0u;
  if (ij.y == 0) dst[count++] = ivec2(n - 1 - ij.x, -1);
  if (ij.y == n - 1) dst[count++] = ivec2(n - 1 - ij.x, n);
  if (ij.x == 0) dst[count++] = ivec2(-1, n - 1 - ij.y);
  if (ij.x == n - 1) dst[count++] = ivec2(n, n - 1 - ij.y);
  if ((ij.x == 0 || ij.x == n - 1) && (ij.y == 0 || ij.y == n - 1)) {
    dst[count++] = ivec2(ij.x == 0 ? n : -1, ij.y == 0 ? n : -1);
  }
  return count;
}

// Writes irradiance texel ij's value into the border texels that copy it (the fused blend: each
// texel's own invocation writes its copies, no pass and no barrier in between).
void store_irradiance_border_copies(uint probe, uvec2 ij, vec4 texel) {
  ivec2 dst[3];
  const uint count = border_copies_of(ivec2(ij), int(field.irradiance_texels), dst);
  const ivec2 base = texel_coord(probe, uvec2(0u), field.irradiance_texels);
  for (uint i = 0u; i < count; ++i) imageStore(irradiance_out, base + dst[i], texel);
}

void store_distance_border_copies(uint probe, uvec2 ij, vec4 texel) {
  ivec2 dst[3];
  const uint count = border_copies_of(ivec2(ij), int(field.distance_texels), dst);
  const ivec2 base = texel_coord(probe, uvec2(0u), field.distance_texels);
  for (uint i = 0u; i < count; ++i) imageStore(distance_out, base + dst[i], texel);
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
