#version 460
#extension GL_GOOGLE_include_directive : require
// Shadow field update, tracing pass. One invocation per probe ray; ShadowDispatch::mode says what
// it does this dispatch:
//   kShadowPassShadow:  from the surfel its probe ray found, one shadow ray towards each kept
//                       light (a jittered point on spherical lights) and, in the AO mode, one
//                       cosine-distributed AO ray; writes the ray's result for the blend;
//   kShadowPassPrimary: traces this update's probe ray and stores the surfel it finds.
// One update runs primary then shadow (two dispatches), or, split (the thesis's Fig. 5.2), both
// in one dispatch: shadow rays from the previous update's surfels, then the new probe ray.
#define DDGI_SHADOW_FIELD_SET 2
#include "common/lights.glsl"
#include "common/dispatch.glsl"
#include "gi/shadow_field.glsl"
#include "gi/shadow_rays.glsl"

layout(push_constant, scalar) uniform Push { ShadowDispatch pc; };
layout(set = kShadowUpdateSet, binding = kShadowUpdateBindingRays, scalar) buffer Rays {
  ShadowRay rays[];
};

ShadowResult shade_surfel(ShadowSurfel s, uint id) {
  ShadowResult result;
  result.direction = s.direction;
  result.distance = s.distance;
  result.flags = s.flags;
  result.ao = 1.0;
  result.pad0 = 0u;
  result.pad1 = 0u;
  for (uint g = 0u; g < kShadowMaxGroups; ++g) result.visibility[g] = vec4(1.0);
  if ((s.flags & (kShadowRayValid | kShadowRayHit)) != (kShadowRayValid | kShadowRayHit)) {
    return result;  // a miss sees nothing that could be shadowed: open, lit
  }
  if ((s.flags & kShadowRayFrontFace) == 0u) {
    // The inside of a closed object: dark, closed.
    result.ao = 0.0;
    for (uint g = 0u; g < kShadowMaxGroups; ++g) result.visibility[g] = vec4(0.0);
    return result;
  }
  const vec3 normal = unpack_normal(s.normal_oct);
  Rng rng = rng_seed(id, shadow.update_index, 0x68e31da4u ^ shadow.seed);
  for (uint light = 0u; light < shadow.light_count; ++light) {
    const vec2 jitter = vec2(rng_next(rng), rng_next(rng));
    result.visibility[light / kShadowLightsPerGroup][light % kShadowLightsPerGroup] =
        shadow_ray_visibility(s.position, normal, scene_lights[light], jitter);
  }
  if ((shadow.flags & kShadowTraceAo) != 0u) {
    result.ao = ao_ray_open(s.position, normal, vec2(rng_next(rng), rng_next(rng)),
                            shadow.ao_distance);
  }
  return result;
}

void main() {
  const uint id = linear_invocation(pc.row_width);
  if (id >= pc.count) return;
  if ((pc.mode & kShadowPassShadow) != 0u) rays[id].result = shade_surfel(rays[id].surfel, id);
  if ((pc.mode & kShadowPassPrimary) == 0u) return;

  const uint probe = id / shadow.rays_per_probe;
  const vec3 origin = shadow_probe_position(probe);
  const vec3 direction = shadow_ray_direction(id % shadow.rays_per_probe);
  // Back faces are not culled: probes inside geometry must see that they are.
  const Hit hit = trace_closest(origin, direction, 0.0, shadow.max_ray_distance);
  ShadowSurfel surfel;
  surfel.direction = direction;
  surfel.pad0 = 0u;
  surfel.pad1 = 0u;
  surfel.pad2 = 0u;
  if (hit.t < 0.0) {
    surfel.position = origin;
    surfel.distance = shadow.max_ray_distance;
    surfel.normal_oct = pack_normal(-direction);
    surfel.flags = kShadowRayValid;
  } else {
    const Surface s = surface_at(hit, direction);
    surfel.position = s.position;
    surfel.distance = hit.t;
    surfel.normal_oct = pack_normal(s.geometric_normal);
    surfel.flags = kShadowRayValid | kShadowRayHit | (s.front_face ? kShadowRayFrontFace : 0u);
  }
  rays[id].surfel = surfel;
}
