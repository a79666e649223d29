#version 460
#extension GL_GOOGLE_include_directive : require
// Primary visibility: one ray per pixel through the pixel centre into the G-buffer.
#include "common/trace.glsl"
#include "common/gbuffer.glsl"
#include "render/primary_ray.glsl"
layout(set = kFrameSet, binding = kFrameBindingGBuffer, scalar) writeonly buffer GBuffer {
  GBufferTexel gbuffer[];
};

void main() {
  const uvec2 pixel = DDGI_INVOCATION_ID.xy;
  if (pixel.x >= pc.width || pixel.y >= pc.height) return;
  const vec3 direction = primary_ray_direction(pixel);
  const Hit hit = trace_closest(pc.camera_position, direction, pc.tmin, pc.tmax);

  GBufferTexel texel;
  if (hit.t < 0.0) {
    texel.position = pc.camera_position;
    texel.normal_oct = pack_normal(-direction);
    texel.geometric_normal_oct = texel.normal_oct;
    texel.emission = sanitize_radiance(environment_radiance(direction));
    texel.albedo_flags = uvec2(0u);
  } else {
    const Surface s = surface_at(hit, direction);
    const vec3 glass = hit.transmittance;
    texel.position = s.position;
    texel.normal_oct = pack_normal(s.normal);
    texel.geometric_normal_oct = pack_normal(s.geometric_normal);
    texel.emission = sanitize_radiance(s.emission * glass);
    // Albedo carries the glass tint: everything reflected passes the glass on its way back.
    texel.albedo_flags = pack_albedo_flags(s.albedo * glass,
                                           kGBufferHit | (s.front_face ? kGBufferFrontFace : 0u));
  }
  gbuffer[pixel.y * pc.width + pixel.x] = texel;
}
