// The surface a G-buffer texel describes, for the frame passes that light it again (direct
// light, paths per pixel). Its albedo carries the glass tint the primary ray passed.
#ifndef DDGI_RENDER_GBUFFER_SURFACE_GLSL
#define DDGI_RENDER_GBUFFER_SURFACE_GLSL

#include "common/gbuffer.glsl"
#include "common/scene.glsl"

Surface gbuffer_surface(GBufferTexel texel) {
  Surface s;
  s.position = texel.position;
  s.normal = unpack_normal(texel.normal_oct);
  s.geometric_normal = unpack_normal(texel.geometric_normal_oct);
  s.albedo = unpack_albedo(texel.albedo_flags);
  s.front_face = (unpack_gbuffer_flags(texel.albedo_flags) & kGBufferFrontFace) != 0u;
  return s;
}

#endif
