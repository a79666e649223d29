#version 460
#extension GL_GOOGLE_include_directive : require
// Field update, pass 3: each irradiance texel blends the cosine-weighted mean radiance of this
// update's rays into its history (2021 paper, eq. 1, perceptual encoding and per-texel
// hysteresis of sec. 4.2-4.3).
#include "common/field_update.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) readonly buffer Rays {
  ProbeRay rays[];
};
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingIrradianceOut, rgba32f) uniform image2D irradiance_out;

float max_component(vec3 v) { return max(v.x, max(v.y, v.z)); }

void main() {
  uint probe, t;
  if (!field_item(probe, t)) return;
  const uint texels = field.irradiance_texels;
  const uvec2 ij = uvec2(t % texels, t / texels);
  const vec3 texel_direction = octahedral_texel_direction(ij, texels);

  const uint first = probe * rays_per_probe_total() + field.fixed_rays;
  vec3 sum = vec3(0.0);
  float weight_sum = 0.0;
  for (uint k = 0u; k < field.rays_per_probe; ++k) {
    const float w = max(0.0, dot(texel_direction, probe_ray_direction(field.fixed_rays + k)));
    if (w > 0.0) {
      sum += w * rays[first + k].radiance;
      weight_sum += w;
    }
  }
  // No ray in this texel's hemisphere this update (very few rays): keep the history.
  if (!(weight_sum > 0.0)) return;

  const ivec2 coord = ivec2(probe_tile_origin(probe, texels) + kAtlasBorder + ij);
  const vec3 fresh = pow(sanitize_radiance(sum / weight_sum), vec3(1.0 / field.irradiance_gamma));
  const vec3 old = imageLoad(irradiance_out, coord).rgb;

  float hysteresis = field.hysteresis;
  if ((probe_states[probe].flags & kProbeResetHistory) != 0u) {
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
