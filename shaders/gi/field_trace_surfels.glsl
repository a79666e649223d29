#version 460
#extension GL_GOOGLE_include_directive : require
// Split field update, pass 1: every blended probe ray records the surfel it finds, for
// field_shade to light (the fused update, field_trace.glsl, does both in one pass).
#include "common/trace.glsl"
#include "common/field_update.glsl"

layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingSurfels, scalar) writeonly buffer
    Surfels {
  ProbeSurfel surfels[];
};

void main() {
  uint probe, local;
  if (!field_item(probe, local)) return;
  const uint r = pc.first_ray + local;
  const uint id = probe * rays_per_probe_total() + r;
  const vec3 origin = probe_position(probe);
  const vec3 direction = probe_ray_direction(r);
  const Hit hit = trace_closest(origin, direction, 0.0, field.max_ray_distance);

  ProbeSurfel surfel;
  if (hit.t < 0.0) {
    surfel.position = origin;
    surfel.distance = field.max_ray_distance;
    surfel.albedo = vec3(0.0);
    surfel.emission = vec3(0.0);
    surfel.normal_oct = pack_normal(-direction);
    surfel.geometric_normal_oct = surfel.normal_oct;
    surfel.flags = 0u;
  } else {
    const Surface s = surface_at(hit, direction);
    surfel.position = s.position;
    surfel.distance = hit.t;
    surfel.albedo = s.albedo;
    surfel.emission = s.emission;
    surfel.normal_oct = pack_normal(s.normal);
    surfel.geometric_normal_oct = pack_normal(s.geometric_normal);
    surfel.flags = kRayHit | (s.front_face ? kRayFrontFace : 0u);
  }
  surfels[id] = surfel;
}
