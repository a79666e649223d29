#version 460
#extension GL_GOOGLE_include_directive : require
// Field update, pass 1: every probe traces its rays (fixed ones first) and records the surfel
// each ray finds.
#include "common/trace.glsl"
#include "common/field_update.glsl"

layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) writeonly buffer Rays {
  ProbeRay rays[];
};

void main() {
  uint probe, local;
  if (!field_item(probe, local)) return;
  const uint r = pc.first_ray + local;
  const uint id = probe * rays_per_probe_total() + r;
  const vec3 origin = probe_position(probe);
  const vec3 direction = probe_ray_direction(r);
  // Back faces are never culled: relocation and classification count them. Fixed rays start a
  // hair behind the probe: a probe lying exactly in a surface's plane never hits that surface
  // from its own position, so it would be neither moved off it nor switched Off; starting
  // behind, it sees the surface at distance ~0, a front face one way and a back face the other,
  // and relocation lifts it off (or classification turns it Off).
  const float min_spacing = min(field.spacing.x, min(field.spacing.y, field.spacing.z));
  const float behind = r < field.fixed_rays ? 1e-3 * min_spacing : 0.0;
  Hit hit =
      trace_closest(origin - behind * direction, direction, 0.0, field.max_ray_distance + behind);
  if (hit.t >= 0.0) hit.t = max(hit.t - behind, 0.0);

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
