// What the frame's two indirect kernels share (indirect.comp: the field at the pixel;
// pixel_paths.glsl: paths per pixel): their inputs, which pixels get indirect light, and adding
// it to the radiance the direct pass wrote.
#ifndef DDGI_RENDER_INDIRECT_PASS_GLSL
#define DDGI_RENDER_INDIRECT_PASS_GLSL

#extension GL_EXT_scalar_block_layout : require
#include "common/gbuffer.glsl"
#include "common/math.glsl"

layout(push_constant, scalar) uniform Push { IndirectConstants pc; };
layout(set = kFrameSet, binding = kFrameBindingGBuffer, scalar) readonly buffer GBuffer {
  GBufferTexel gbuffer[];
};
layout(set = kFrameSet, binding = kFrameBindingRadiance, scalar) buffer Radiance {
  vec4 radiance[];
};

// The G-buffer texel of `pixel`, when it gets indirect light: inside the frame, a primary hit,
// and a view that shows indirect light.
bool indirect_texel(uvec2 pixel, out GBufferTexel texel) {
  if (pixel.x >= pc.width || pixel.y >= pc.height) return false;
  if (pc.view != kViewFull && pc.view != kViewIndirect && pc.view != kViewProbes) return false;
  texel = gbuffer[pixel.y * pc.width + pixel.x];
  return (unpack_gbuffer_flags(texel.albedo_flags) & kGBufferHit) != 0u;
}

void add_indirect(uvec2 pixel, vec3 indirect) {
  radiance[pixel.y * pc.width + pixel.x].rgb += sanitize_radiance(indirect);
}

#endif
