#version 460
#extension GL_GOOGLE_include_directive : require
// The benchmark's baseline for primary visibility (ddgi-bench): the same camera rays and hit
// groups, traced by a kernel that writes only the hit distance (into the G-buffer texel's
// first float, which the next frame overwrites).
#include "common/trace.glsl"
#include "render/primary_ray.glsl"

layout(set = kFrameSet, binding = kFrameBindingGBuffer, scalar) writeonly buffer GBuffer {
  GBufferTexel gbuffer[];
};

void main() {
  const uvec2 pixel = DDGI_INVOCATION_ID.xy;
  if (pixel.x >= pc.width || pixel.y >= pc.height) return;
  const Hit hit =
      trace_closest(pc.camera_position, primary_ray_direction(pixel), pc.tmin, pc.tmax);
  gbuffer[pixel.y * pc.width + pixel.x].position.x = hit.t;
}
