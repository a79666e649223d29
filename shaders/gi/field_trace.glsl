#version 460
#extension GL_GOOGLE_include_directive : require
// Field update, pass 1: every probe traces its rays (fixed ones first) and records the surfel
// each ray finds.
#include "common/trace.glsl"
#include "common/field.glsl"
#include "common/dispatch.glsl"

layout(push_constant, scalar) uniform Push { FieldDispatch pc; };
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) writeonly buffer Rays {
  ProbeRay rays[];
};

void main() {
  const uint id = linear_invocation(pc.row_width);
  if (id >= pc.count) return;
  const uint total = rays_per_probe_total();
  const uint probe = id / total;
  const vec3 origin = probe_position(probe);
  const vec3 direction = probe_ray_direction(id % total);
  // Back faces are never culled: relocation and classification count them.
  const Hit hit = trace_closest(origin, direction, 0.0, field.max_ray_distance);

  ProbeRay ray;
  ray.radiance = vec3(0.0);
  if (hit.t < 0.0) {
    ray.position = origin;
    ray.distance = field.max_ray_distance;
    ray.albedo = vec3(0.0);
    ray.emission = vec3(0.0);
    ray.normal_oct = pack_normal(-direction);
    ray.geometric_normal_oct = ray.normal_oct;
    ray.flags = 0u;
  } else {
    const Surface s = surface_at(hit, direction);
    ray.position = s.position;
    ray.distance = hit.t;
    ray.albedo = s.albedo;
    ray.emission = s.emission;
    ray.normal_oct = pack_normal(s.normal);
    ray.geometric_normal_oct = pack_normal(s.geometric_normal);
    ray.flags = kRayHit | (s.front_face ? kRayFrontFace : 0u);
  }
  rays[id] = ray;
}
