#version 460
#extension GL_GOOGLE_include_directive : require
// Indirect diffuse light from the irradiance field at every primary hit: albedo x M.
#extension GL_EXT_scalar_block_layout : require
#include "common/field.glsl"
#include "render/indirect_pass.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

void main() {
  const uvec2 pixel = gl_GlobalInvocationID.xy;
  GBufferTexel texel;
  if (!indirect_texel(pixel, texel)) return;
  const vec3 n = unpack_normal(texel.normal_oct);
  const vec3 to_camera = safe_normalize(pc.camera_position - texel.position, n);
  add_indirect(pixel, unpack_albedo(texel.albedo_flags) *
                          sample_irradiance(texel.position, n, to_camera));
}
