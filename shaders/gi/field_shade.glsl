#version 460
#extension GL_GOOGLE_include_directive : require
// Split field update, pass 2: lights the surfel each blended ray found (field_trace_surfels)
// and writes the ray's radiance and distance. The thin glass in front of the hit is found by a
// second, transmittance-type ray: the split update is kept as the fused one's reference
// (tests compare their atlases) and as the benchmark's comparison.
#include "gi/probe_ray_radiance.glsl"

layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingSurfels, scalar) readonly buffer Surfels {
  ProbeSurfel surfels[];
};
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) writeonly buffer Rays {
  ProbeRay rays[];
};

void main() {
  uint probe, local;
  if (!field_item(probe, local)) return;
  const uint r = field.fixed_rays + local;
  const uint index = probe * rays_per_probe_total() + r;
  const ProbeSurfel surfel = surfels[index];
  const vec3 origin = probe_position(probe);
  const vec3 direction = probe_ray_direction(r);
  const bool hit = (surfel.flags & kRayHit) != 0u;
  const bool front_face = (surfel.flags & kRayFrontFace) != 0u;

  vec3 radiance = vec3(0.0);
  if (!hit) {
    radiance = environment_radiance(direction);
  } else if (front_face) {
    Surface s;
    s.position = surfel.position;
    s.normal = unpack_normal(surfel.normal_oct);
    s.geometric_normal = unpack_normal(surfel.geometric_normal_oct);
    s.albedo = surfel.albedo;
    s.emission = surfel.emission;
    s.front_face = true;
    radiance = probe_hit_radiance(s, direction, index);
  }
  const float t = hit ? surfel.distance : field.max_ray_distance;
  if ((scene.flags & kSceneHasTransmission) != 0u) {
    radiance *= trace_transmittance(origin, direction, 0.0, t);
  }
  ProbeRay ray;
  ray.radiance = sanitize_radiance(radiance);
  ray.distance = encode_ray_distance(hit, front_face, surfel.distance);
  rays[index] = ray;
}
