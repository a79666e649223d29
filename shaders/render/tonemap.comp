#version 460
#extension GL_GOOGLE_include_directive : require
// Exposure, tone mapping and sRGB encoding of the HDR radiance into RGBA8.
#extension GL_EXT_scalar_block_layout : require
#include "common/math.glsl"
#include "shared/frame_data.h"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(push_constant, scalar) uniform Push { TonemapConstants pc; };
layout(set = kFrameSet, binding = kFrameBindingRadiance, scalar) readonly buffer Radiance {
  vec4 radiance[];
};
layout(set = kFrameSet, binding = kFrameBindingLdr, scalar) writeonly buffer Ldr {
  uint ldr[];
};

// Narkowicz's fit of the ACES filmic curve (2015).
vec3 aces(vec3 x) {
  return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

void main() {
  const uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= pc.width || pixel.y >= pc.height) return;
  const uint index = pixel.y * pc.width + pixel.x;
  vec3 c = sanitize_radiance(radiance[index].rgb) * pc.exposure;
  if (pc.tonemap == kTonemapAces) {
    c = aces(c);
  } else if (pc.tonemap == kTonemapReinhard) {
    c = c / (1.0 + c);
  }
  const uvec3 q = uvec3(vec3(linear_to_srgb(c.r), linear_to_srgb(c.g), linear_to_srgb(c.b)) *
                            255.0 + 0.5);
  ldr[index] = q.r | (q.g << 8) | (q.b << 16) | (255u << 24);
}
