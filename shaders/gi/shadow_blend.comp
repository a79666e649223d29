#version 460
#extension GL_GOOGLE_include_directive : require
// Shadow field update, blend pass: one invocation per interior texel w of every probe's maps.
// Visibility of each kept light (and AO) blends the rays' results with weight max(0, w.r)^k_v,
// the distance moments with max(0, w.r)^k_d, r being the probe ray's direction, then mixes them
// with the texel's history by the hysteresis (thesis eq. 5.2-5.3; docs/shadow-field.md says why
// r and not the shadow ray's direction).
#define DDGI_SHADOW_FIELD_SET 2
#include "common/dispatch.glsl"
#include "gi/shadow_field.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(push_constant, scalar) uniform Push { ShadowDispatch pc; };
layout(set = kShadowUpdateSet, binding = kShadowUpdateBindingRays, scalar) readonly buffer Rays {
  ShadowRay rays[];
};
layout(set = kShadowUpdateSet, binding = kShadowUpdateBindingVisibilityOut,
       rgba32f) uniform image2D visibility_out;
layout(set = kShadowUpdateSet, binding = kShadowUpdateBindingMomentsOut,
       rgba32f) uniform image2D moments_out;

void main() {
  const uint id = linear_invocation(pc.row_width);
  if (id >= pc.count) return;
  const uint probe = id / pc.per_probe;
  const uint t = id % pc.per_probe;
  const uvec2 ij = uvec2(t % shadow.texels, t / shadow.texels);
  const vec3 texel_direction = shadow_texel_direction(ij);

  vec4 visibility[kShadowMaxGroups];
  for (uint g = 0u; g < kShadowMaxGroups; ++g) visibility[g] = vec4(0.0);
  float ao = 0.0, visibility_weight = 0.0, distance_weight = 0.0;
  vec2 moments = vec2(0.0);
  const uint first = probe * shadow.rays_per_probe;
  for (uint k = 0u; k < shadow.rays_per_probe; ++k) {
    const ShadowResult ray = rays[first + k].result;
    if ((ray.flags & kShadowRayValid) == 0u) continue;
    const float c = dot(texel_direction, ray.direction);
    if (c <= 0.0) continue;
    const float wv = pow(c, shadow.visibility_exponent);
    const float wd = pow(c, shadow.distance_exponent);
    for (uint g = 0u; g < kShadowMaxGroups; ++g) visibility[g] += wv * ray.visibility[g];
    ao += wv * ray.ao;
    visibility_weight += wv;
    float d = ray.distance;
    if ((ray.flags & (kShadowRayHit | kShadowRayFrontFace)) == kShadowRayHit) {
      d *= shadow.backface_distance_scale;
    }
    d = clamp(d, 0.0, shadow.max_visibility_distance);
    moments += wd * vec2(d, d * d);
    distance_weight += wd;
  }

  const float hysteresis = (shadow.flags & kShadowResetHistory) != 0u ? 0.0 : shadow.hysteresis;
  const uint groups = (shadow.light_count + kShadowLightsPerGroup - 1u) / kShadowLightsPerGroup;
  const ivec2 coord = shadow_map_origin(probe, 0u) + ivec2(ij);
  const vec4 old = imageLoad(moments_out, coord);
  vec4 blended = old;
  // Visibility is a weighted exponential moving average: the texel keeps its history's weight
  // (moments.w) so that rays far from its direction, with tiny weights, change it little, while
  // a ray right on it counts fully. Normalising each update on its own would let the nearest
  // ray, however far, set the value, blurring the map over the spacing between rays.
  const float history = hysteresis * old.w;
  const float total = history + visibility_weight;
  if (total > 0.0 && visibility_weight > 0.0) {
    for (uint g = 0u; g < groups; ++g) {
      const ivec2 c = shadow_map_origin(probe, g) + ivec2(ij);
      imageStore(visibility_out, c, (history * imageLoad(visibility_out, c) + visibility[g]) / total);
    }
    blended.w = total;
  } else {
    blended.w = history;
  }
  if (distance_weight > 0.0) blended.xy = mix(moments / distance_weight, old.xy, hysteresis);
  if (visibility_weight > 0.0 && (shadow.flags & kShadowTraceAo) != 0u) {
    const bool fresh_ao = (shadow.flags & kShadowResetAo) != 0u;
    blended.z = mix(ao / visibility_weight, old.z, fresh_ao ? 0.0 : hysteresis);
  }
  imageStore(moments_out, coord, blended);
}
