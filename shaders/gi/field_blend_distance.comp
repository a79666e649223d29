#version 460
#extension GL_GOOGLE_include_directive : require
// Field update, pass 4: each distance texel blends the power-cosine weighted mean of hit
// distances and squared distances (thesis eq. 4.14-4.16). Back-face hits are shortened
// (2021 paper, sec. 4.1); everything is clamped to the visibility range.
#include "common/field_update.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) readonly buffer Rays {
  ProbeRay rays[];
};
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingDistanceOut, rg32f) uniform image2D distance_out;

void main() {
  uint probe, t;
  if (!field_item(probe, t)) return;
  const uint texels = field.distance_texels;
  const uvec2 ij = uvec2(t % texels, t / texels);
  const vec3 texel_direction = octahedral_texel_direction(ij, texels);

  const uint first = probe * rays_per_probe_total() + field.fixed_rays;
  vec2 sum = vec2(0.0);
  float weight_sum = 0.0;
  for (uint k = 0u; k < field.rays_per_probe; ++k) {
    const float c = dot(texel_direction, probe_ray_direction(field.fixed_rays + k));
    if (c <= 0.0) continue;
    const float w = pow(c, field.distance_exponent);
    const ProbeRay ray = rays[first + k];
    float d = ray.distance;
    if ((ray.flags & (kRayHit | kRayFrontFace)) == kRayHit) d *= field.backface_distance_scale;
    d = clamp(d, 0.0, field.max_visibility_distance);
    sum += w * vec2(d, d * d);
    weight_sum += w;
  }
  if (!(weight_sum > 0.0)) return;

  const ivec2 coord = ivec2(probe_tile_origin(probe, texels) + kAtlasBorder + ij);
  const vec2 fresh = sum / weight_sum;
  const vec2 old = imageLoad(distance_out, coord).rg;
  const float hysteresis = (probe_states[probe].flags & kProbeResetHistory) != 0u
                               ? 0.0
                               : field.distance_hysteresis;
  imageStore(distance_out, coord, vec4(mix(fresh, old, hysteresis), 0.0, 0.0));
}
