#version 460
#extension GL_GOOGLE_include_directive : require
// Indirect light per pixel traced, not read (field parameter pixel_paths > 0; in place of
// indirect.comp): each primary hit's indirect light is the mean of pixel_paths cosine-weighted
// paths of at most pixel_path_vertices vertices that read the field only where they end
// (gi/field_paths.glsl, the probe paths' rule). Light a probe grid cannot hold, the near field
// of cavities and gaps narrower than the probe spacing, then reaches the pixel along the path,
// at the noise of a few paths per pixel. The seed is fixed per pixel, as the direct pass's is:
// a still camera sees a still image.
#include "gi/field_paths.glsl"
#include "render/gbuffer_surface.glsl"
#include "render/indirect_pass.glsl"

void main() {
  const uvec2 pixel = DDGI_INVOCATION_ID.xy;
  GBufferTexel texel;
  if (!indirect_texel(pixel, texel)) return;
  const Surface s = gbuffer_surface(texel);
  Rng rng = rng_seed(pixel.x, pixel.y, 0x27d4eb2fu);
  vec3 sum = vec3(0.0);
  for (uint path = 0u; path < pc.paths; ++path) {
    sum += traced_irradiance(s, pc.path_vertices, rng);
  }
  add_indirect(pixel, s.albedo * sum / float(pc.paths));
}
