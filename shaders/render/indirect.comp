#version 460
#extension GL_GOOGLE_include_directive : require
// Indirect diffuse light from the irradiance field at every primary hit: albedo x M.
#extension GL_EXT_scalar_block_layout : require
#include "common/field.glsl"
#include "common/gbuffer.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(push_constant, scalar) uniform Push { IndirectConstants pc; };
layout(set = kFrameSet, binding = kFrameBindingGBuffer, scalar) readonly buffer GBuffer {
  GBufferTexel gbuffer[];
};
layout(set = kFrameSet, binding = kFrameBindingRadiance, scalar) buffer Radiance {
  vec4 radiance[];
};

void main() {
  const uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= pc.width || pixel.y >= pc.height) return;
  const uint index = pixel.y * pc.width + pixel.x;
  const GBufferTexel texel = gbuffer[index];
  if ((unpack_gbuffer_flags(texel.albedo_flags) & kGBufferHit) == 0u) return;
  if (pc.view != kViewFull && pc.view != kViewIndirect && pc.view != kViewProbes) return;
  const vec3 n = unpack_normal(texel.normal_oct);
  const vec3 to_camera = safe_normalize(pc.camera_position - texel.position, n);
  const vec3 indirect = unpack_albedo(texel.albedo_flags) *
                        sample_irradiance(texel.position, n, to_camera);
  radiance[index].rgb += sanitize_radiance(indirect);
}
