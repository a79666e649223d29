#version 460
#extension GL_GOOGLE_include_directive : require
// Direct light at each primary hit: punctual lights under the frame's DirectMode (traced shadow
// rays, the shadow field, none), plus what the surface emits. Writes linear HDR radiance.
// Compiled a second time as direct_shadow_field with DDGI_SHADOW_FIELD_SET=2 (the shadow field),
// a third as direct_ao_cache with DDGI_WORLD_CACHE_SET=2 (the world cache's AO).
#include "gi/shadow_direct.glsl"
#ifdef DDGI_WORLD_CACHE_SET
#include "common/world_cache.glsl"
#endif
#include "common/emitter_direct.glsl"
#include "render/gbuffer_surface.glsl"

layout(push_constant, scalar) uniform Push { DirectConstants pc; };
layout(set = kFrameSet, binding = kFrameBindingGBuffer, scalar) readonly buffer GBuffer {
  GBufferTexel gbuffer[];
};
layout(set = kFrameSet, binding = kFrameBindingRadiance, scalar) writeonly buffer Radiance {
  vec4 radiance[];
};

// The open fraction of the sky at s in the AO modes of the world cache: traced (ao_samples
// stratified rays), or read from the cache, where nothing cached near s yet gets one traced ray.
float ambient_occlusion(Surface s, inout Rng rng) {
#ifdef DDGI_WORLD_CACHE_SET
  if (pc.mode == kDirectAoCache) {
    const float cached = cache_read(s.position, s.normal, length(s.position - pc.camera_position));
    if (cached >= 0.0) return cached;
    return ao_ray_open(s.position, s.normal, vec2(rng_next(rng), rng_next(rng)), pc.ao_distance);
  }
#endif
  const uint samples = max(pc.ao_samples, 1u);
  float open = 0.0;
  for (uint i = 0u; i < samples; ++i) {
    const vec2 u = vec2((float(i) + rng_next(rng)) / float(samples), rng_next(rng));
    open += ao_ray_open(s.position, s.normal, u, pc.ao_distance);
  }
  return open / float(samples);
}

void main() {
  const uvec2 pixel = DDGI_INVOCATION_ID.xy;
  if (pixel.x >= pc.width || pixel.y >= pc.height) return;
  const uint index = pixel.y * pc.width + pixel.x;
  const GBufferTexel texel = gbuffer[index];
  const uint flags = unpack_gbuffer_flags(texel.albedo_flags);
  // The indirect view is the frame less what is seen directly (an emitter, the environment
  // behind a missed primary ray) and less what punctual lights send straight to the surface:
  // the part the field carries, plus sampled emitters' light, which the field carries when they
  // are not sampled. The path tracer's field-indirect view, which ddgi-eval compares it with,
  // is the same part.
  vec3 result = pc.view == kViewIndirect ? vec3(0.0) : texel.emission;
  if ((flags & kGBufferHit) != 0u) {
    const Surface s = gbuffer_surface(texel);
    Rng rng = rng_seed(pixel.x, pixel.y, 0x9e3779b9u);
    const vec3 to_camera = safe_normalize(pc.camera_position - s.position, s.normal);
    const bool world_ao = pc.mode == kDirectAoTraced || pc.mode == kDirectAoCache;
    vec3 direct = direct_light(s, world_ao ? kDirectTracedShadows : pc.mode, pc.light_samples,
                               to_camera, (pc.flags & kDirectAddSky) != 0u, rng);
    // As in the shadow field's AO mode, the sky comes through AO only when no field brings it.
    if (world_ao && (pc.flags & kDirectAddSky) != 0u) {
      direct += s.albedo * ambient_occlusion(s, rng) * environment_radiance(s.normal);
    }
    const vec3 emitters = (pc.flags & kDirectSampleEmitters) != 0u
                              ? emitter_direct(s, pc.emitter_samples, rng)
                              : vec3(0.0);
    if (pc.view == kViewAlbedo) {
      result = s.albedo;
    } else if (pc.view == kViewNormal) {
      result = s.normal * 0.5 + 0.5;
#ifdef DDGI_WORLD_CACHE_SET
    } else if (pc.view == kViewCachePoints) {
      result = cache_point_colour(s.position, s.normal, length(s.position - pc.camera_position));
#endif
    } else if (pc.view == kViewIndirect) {
      result = emitters;
    } else {
      result += direct + emitters;
    }
  }
  radiance[index] = vec4(sanitize_radiance(result), 1.0);
}
