#version 460
#extension GL_GOOGLE_include_directive : require
// The world cache's AO samples (docs/world-cache.md): at each primary hit, one cosine-distributed
// AO ray, added to the implicit point the stochastic choice picks near the hit, at a level drawn
// between the two around the hit's continuous level (so each level gets its share of samples).
#define DDGI_WORLD_CACHE_SET 2
#include "common/world_cache.glsl"
#include "gi/shadow_rays.glsl"
#include "render/gbuffer_surface.glsl"

layout(push_constant, scalar) uniform Push { WorldCacheDispatch pc; };
layout(set = kFrameSet, binding = kFrameBindingGBuffer, scalar) readonly buffer GBuffer {
  GBufferTexel gbuffer[];
};

void main() {
  const uvec2 pixel = DDGI_INVOCATION_ID.xy;
  if (pixel.x >= pc.width || pixel.y >= pc.height) return;
  const GBufferTexel texel = gbuffer[pixel.y * pc.width + pixel.x];
  if ((unpack_gbuffer_flags(texel.albedo_flags) & kGBufferHit) == 0u) return;
  const Surface s = gbuffer_surface(texel);
  Rng rng = rng_seed(pixel.x, pixel.y, cache.frame * 0x2c1b3c6du + 0x51ed27u);
  const float level = cache_level(length(s.position - cache.camera_position));
  const uint drawn = min(uint(level) + (rng_next(rng) < fract(level) ? 1u : 0u), cache.levels - 1u);
  const CachePoint p =
      cache_pick_point(s.position, drawn, cache_normal_bucket(s.normal), rng_next(rng));
  const float open = ao_ray_open(s.position, s.normal, vec2(rng_next(rng), rng_next(rng)),
                                 cache.ao_distance);
  cache_add_sample(cache_find_or_insert(p), open);
}
