#version 460
#extension GL_GOOGLE_include_directive : require
// Split field update, pass 3: each irradiance texel blends the cosine-weighted mean radiance of
// this update's rays into its history, one invocation per texel reading every ray (the fused
// update does the same per probe in field_blend.comp).
#include "gi/field_blend.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) readonly buffer Rays {
  ProbeRay rays[];
};

void main() {
  uint probe, t;
  if (!field_item(probe, t)) return;
  const uint texels = field.irradiance_texels;
  const uvec2 ij = uvec2(t % texels, t / texels);
  const vec3 texel_direction = octahedral_texel_direction(ij, texels);

  const uint first = probe * rays_per_probe_total() + field.fixed_rays;
  const vec4 history = irradiance_history(probe, ij);
  vec3 sum = vec3(0.0);
  float weight_sum = 0.0;
  for (uint k = 0u; k < field.rays_per_probe; ++k) {
    const float w = max(0.0, dot(texel_direction, probe_ray_direction(field.fixed_rays + k)));
    if (w > 0.0) {
      sum += w * rays[first + k].radiance;
      weight_sum += w;
    }
  }
  const bool reset = (probe_states[probe].flags & kProbeResetHistory) != 0u;
  vec2 seen;  // adaptive rays take the fused blend only (IrradianceField::check_path_fits)
  blend_irradiance_texel(probe, ij, history, sum, weight_sum, reset, false, seen);
}
