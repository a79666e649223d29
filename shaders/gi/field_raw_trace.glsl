#version 460
#extension GL_GOOGLE_include_directive : require
// The benchmark's baseline (ddgi-bench): the field update's blended probe rays, the same
// origins, directions, distance range and hit groups (alpha masks and glass included), traced
// by a kernel that does nothing else and writes only the hit distance. The update's cost over
// this one's is what shading and blending add to the rays.
#include "common/trace.glsl"
#include "common/field_update.glsl"

layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) writeonly buffer Rays {
  ProbeRay rays[];
};

void main() {
  uint probe, local;
  if (!field_lit_item(probe, local)) return;
  const uint r = pc.first_ray + local;
  const Hit hit = trace_closest(probe_position(probe), probe_ray_direction(r), 0.0,
                                field.max_ray_distance);
  rays[probe * rays_per_probe_total() + r].distance = hit.t;
}
