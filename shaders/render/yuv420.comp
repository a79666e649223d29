#version 460
#extension GL_GOOGLE_include_directive : require
// The tone-mapped RGBA8 image as JPEG's YCbCr 4:2:0 planes (shared/frame_data.h, Yuv420Layout):
// the frame reads back 1.5 bytes per pixel instead of 4, and the JPEG encoder skips its colour
// conversion and chroma downsampling. JFIF's full-range BT.601 matrix; chroma is the mean of
// each 2x2 block. Pixels past the image's right or bottom edge (row padding) repeat the edge.
// One invocation converts 8x2 pixels, so every write is a whole 32-bit word.
#extension GL_EXT_scalar_block_layout : require
#include "shared/frame_data.h"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(push_constant, scalar) uniform Push { Yuv420Layout pc; };
layout(set = kFrameSet, binding = kFrameBindingLdr, scalar) readonly buffer Ldr { uint ldr[]; };
layout(set = kFrameSet, binding = kFrameBindingYuv420, scalar) writeonly buffer Yuv420 {
  uint yuv420[];
};

vec3 rgb_at(ivec2 pixel) {
  pixel = clamp(pixel, ivec2(0), ivec2(pc.width - 1, pc.height - 1));
  const uint packed = ldr[uint(pixel.y) * pc.width + uint(pixel.x)];
  return vec3(packed & 255u, (packed >> 8) & 255u, (packed >> 16) & 255u);
}

// Values in [0, 255] before rounding; the clamp only guards against float rounding.
uint to_byte(float value) { return uint(clamp(floor(value + 0.5), 0.0, 255.0)); }

uint luma(vec3 rgb) { return to_byte(dot(rgb, vec3(0.299, 0.587, 0.114))); }

void main() {
  const uvec2 block = gl_GlobalInvocationID.xy;
  if (block.x * 8u >= pc.y_stride || block.y * 2u >= pc.y_rows) return;
  const ivec2 origin = ivec2(block * uvec2(8u, 2u));
  uint luma_words[4] = uint[4](0u, 0u, 0u, 0u);  // top row: [0], [1]; bottom row: [2], [3]
  uint cb_word = 0u;
  uint cr_word = 0u;
  for (int quad = 0; quad < 4; ++quad) {  // the four 2x2 blocks, left to right
    vec3 sum = vec3(0.0);
    for (int dy = 0; dy < 2; ++dy) {
      for (int dx = 0; dx < 2; ++dx) {
        const int x = quad * 2 + dx;
        const vec3 rgb = rgb_at(origin + ivec2(x, dy));
        sum += rgb;
        luma_words[dy * 2 + x / 4] |= luma(rgb) << (8 * (x % 4));
      }
    }
    const vec3 mean = sum * 0.25;
    cb_word |= to_byte(128.0 + dot(mean, vec3(-0.168736, -0.331264, 0.5))) << (8 * quad);
    cr_word |= to_byte(128.0 + dot(mean, vec3(0.5, -0.418688, -0.081312))) << (8 * quad);
  }
  const uint top = (uint(origin.y) * pc.y_stride) / 4u + block.x * 2u;
  const uint bottom = top + pc.y_stride / 4u;
  yuv420[top] = luma_words[0];
  yuv420[top + 1u] = luma_words[1];
  yuv420[bottom] = luma_words[2];
  yuv420[bottom + 1u] = luma_words[3];
  const uint chroma = (block.y * pc.chroma_stride) / 4u + block.x;
  yuv420[pc.cb_offset / 4u + chroma] = cb_word;
  yuv420[pc.cr_offset / 4u + chroma] = cr_word;
}
