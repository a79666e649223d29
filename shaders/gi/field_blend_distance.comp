#version 460
#extension GL_GOOGLE_include_directive : require
// Split field update, pass 4: each distance texel blends the power-cosine weighted mean of hit
// distances and squared distances, one invocation per texel reading every ray (the fused
// update does the same per probe in field_blend.comp).
#include "gi/field_blend.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) readonly buffer Rays {
  ProbeRay rays[];
};

void main() {
  uint probe, t;
  if (!field_item(probe, t)) return;
  const uint texels = field.distance_texels;
  const uvec2 ij = uvec2(t % texels, t / texels);
  const vec3 texel_direction = octahedral_texel_direction(ij, texels);

  const uint first = probe * rays_per_probe_total() + field.fixed_rays;
  const vec4 history = distance_history(probe, ij);
  vec2 sum = vec2(0.0);
  float weight_sum = 0.0;
  for (uint k = 0u; k < field.rays_per_probe; ++k) {
    const float c = dot(texel_direction, probe_ray_direction(field.fixed_rays + k));
    if (c <= 0.0) continue;
    const float w = pow(c, field.distance_exponent);
    const float d = blended_ray_distance(rays[first + k].distance);
    sum += w * vec2(d, d * d);
    weight_sum += w;
  }
  const bool reset = (probe_states[probe].flags & kProbeResetHistory) != 0u;
  blend_distance_texel(probe, ij, history, sum, weight_sum, reset);
}
