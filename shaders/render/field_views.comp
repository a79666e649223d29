#version 460
#extension GL_GOOGLE_include_directive : require
// Inspection views of the irradiance field, drawn over the frame:
//  probes: every probe as a sphere, shaded by the irradiance it stores in the direction of the
//          sphere's normal (so a probe's sphere is a small picture of what it sees), with a rim
//          coloured by its state: green vigilant, yellow awake, blue sleeping, red off, and in
//          a field of several volumes a ring inside the rim coloured by its volume (magenta,
//          cyan, orange, white, ... finest first);
//  atlas:  the irradiance atlas (decoded) over the top half, the mean-distance atlas
//          (normalised to the visibility range) over the bottom half.
#extension GL_EXT_scalar_block_layout : require
#include "common/field.glsl"
#include "common/gbuffer.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(push_constant, scalar) uniform Push { FieldViewConstants pc; };
layout(set = kFrameSet, binding = kFrameBindingGBuffer, scalar) readonly buffer GBuffer {
  GBufferTexel gbuffer[];
};
layout(set = kFrameSet, binding = kFrameBindingRadiance, scalar) buffer Radiance {
  vec4 radiance[];
};

// Nearest ray-sphere hit in (0, tmax), or tmax.
float sphere_hit(vec3 o, vec3 d, vec3 c, float r, float tmax) {
  const vec3 oc = o - c;
  const float b = dot(oc, d);
  const float disc = b * b - (dot(oc, oc) - r * r);
  if (disc < 0.0) return tmax;
  const float t = -b - sqrt(disc);
  return t > 0.0 && t < tmax ? t : tmax;
}

// The nearest probe sphere of the selected volume the ray hits before best_t, if any: walks the
// grid cells the ray crosses (3D-DDA) and tests the 8 probes around each; probes stay within
// half a cell of their grid point, so a sphere is always found from its cells.
void nearest_volume_probe(vec3 o, vec3 d, inout float best_t, inout uint best_probe) {
  const vec3 lo = field_grid.origin - field_grid.spacing;
  const vec3 hi = field_grid.origin + field_grid.spacing * vec3(field_grid.counts);
  const vec3 inv = 1.0 / d;
  const vec3 t0 = (lo - o) * inv, t1 = (hi - o) * inv;
  const float enter = max(max(min(t0.x, t1.x), min(t0.y, t1.y)), max(min(t0.z, t1.z), 0.0));
  const float leave = min(min(max(t0.x, t1.x), max(t0.y, t1.y)), min(max(t0.z, t1.z), best_t));
  if (enter >= leave) return;

  vec3 p = o + d * enter;
  ivec3 cell = ivec3(floor((p - field_grid.origin) / field_grid.spacing));
  const ivec3 step_dir = ivec3(sign(d));
  const vec3 next_boundary = field_grid.origin + field_grid.spacing * (vec3(cell) + max(vec3(step_dir), 0.0));
  vec3 t_max = enter + (next_boundary - p) * inv;
  const vec3 t_delta = abs(field_grid.spacing * inv);
  const uint found_before = best_probe;
  for (int i = 0; i < 4 * (field_grid.counts.x + field_grid.counts.y + field_grid.counts.z) + 8; ++i) {
    for (uint c = 0u; c < 8u; ++c) {
      const ivec3 coord = cell + ivec3(c & 1u, (c >> 1) & 1u, (c >> 2) & 1u);
      if (any(lessThan(coord, ivec3(0))) || any(greaterThanEqual(coord, field_grid.counts))) continue;
      const uint probe = probe_index(coord);
      const float t = sphere_hit(o, d, probe_position(probe), pc.probe_radius, best_t);
      if (t < best_t) {
        best_t = t;
        best_probe = probe;
      }
    }
    const float t_next = min(t_max.x, min(t_max.y, t_max.z));
    if (best_probe != found_before && best_t <= t_next) break;  // nothing nearer further on
    if (t_next > leave) break;
    if (t_max.x <= t_max.y && t_max.x <= t_max.z) {
      cell.x += step_dir.x;
      t_max.x += t_delta.x;
    } else if (t_max.y <= t_max.z) {
      cell.y += step_dir.y;
      t_max.y += t_delta.y;
    } else {
      cell.z += step_dir.z;
      t_max.z += t_delta.z;
    }
  }
}

// Every volume's probes as spheres.
vec3 probe_view(vec3 o, vec3 d, float scene_t, vec3 background) {
  float best_t = scene_t;
  uint best_probe = 0xFFFFFFFFu;
  for (uint v = 0u; v < volumes[0].volume_count; ++v) {
    field_volume = v;
    nearest_volume_probe(o, d, best_t, best_probe);
  }
  if (best_probe == 0xFFFFFFFFu) return background;
  select_probe_volume(best_probe);
  const vec3 n = normalize(o + d * best_t - probe_position(best_probe));
  const vec3 irradiance = probe_irradiance(best_probe, n);
  const vec3 state_colors[4] = vec3[4](vec3(0.1, 0.9, 0.1), vec3(0.9, 0.8, 0.1),
                                       vec3(0.2, 0.4, 1.0), vec3(0.9, 0.1, 0.1));
  const float facing = abs(dot(n, d));
  // A field of several volumes rings each sphere inside its rim with its volume's colour.
  const vec3 volume_colors[kMaxFieldVolumes] = vec3[kMaxFieldVolumes](
      vec3(0.9, 0.2, 0.9), vec3(0.1, 0.9, 0.9), vec3(1.0, 0.5, 0.0), vec3(1.0, 1.0, 1.0),
      vec3(0.5, 0.2, 1.0), vec3(0.0, 0.5, 0.5), vec3(1.0, 0.6, 0.7), vec3(0.5, 0.5, 0.0));
  if (volumes[0].volume_count > 1u && facing > 0.35 && facing < 0.5) {
    return volume_colors[field_volume];
  }
  const float rim = smoothstep(0.35, 0.1, facing);
  return mix(irradiance, state_colors[min(probe_state(best_probe), 3u)], rim);
}

vec3 atlas_view(uvec2 pixel) {
  const float half_height = float(pc.height) * 0.5;
  if (float(pixel.y) < half_height) {
    const vec2 uv = (vec2(pixel) + 0.5) / vec2(pc.width, half_height);
    const vec3 encoded = textureLod(irradiance_atlas, uv, 0.0).rgb;
    return pow(max(encoded, vec3(0.0)), vec3(field.irradiance_gamma));
  }
  const vec2 uv = (vec2(pixel) - vec2(0.0, half_height) + 0.5) / vec2(pc.width, half_height);
  return vec3(textureLod(distance_atlas, uv, 0.0).r / field_grid.max_visibility_distance);
}

void main() {
  const uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= pc.width || pixel.y >= pc.height) return;
  const uint index = pixel.y * pc.width + pixel.x;
  vec3 result = radiance[index].rgb;
  if (pc.view == kViewAtlas) {
    result = atlas_view(pixel);
  } else if (pc.view == kViewProbes) {
    const vec2 ndc = (vec2(pixel) + 0.5) / vec2(pc.width, pc.height) * 2.0 - 1.0;
    const vec3 d = normalize(pc.camera_forward + ndc.x * pc.camera_right - ndc.y * pc.camera_up);
    const GBufferTexel texel = gbuffer[index];
    const bool hit = (unpack_gbuffer_flags(texel.albedo_flags) & kGBufferHit) != 0u;
    const float scene_t = hit ? dot(texel.position - pc.camera_position, d) : kFloatMax;
    result = probe_view(pc.camera_position, d, scene_t, result);
  }
  radiance[index].rgb = sanitize_radiance(result);
}
