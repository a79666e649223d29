#version 460
#extension GL_GOOGLE_include_directive : require
// Probe management from each probe's fixed rays (traced just before):
//  relocate: a probe that sees mostly back faces is inside geometry: it steps out through the
//            closest back face; a probe too close to a front face steps away from it. Offsets
//            stay within probe_offset_limit x spacing of the grid point (2021 paper, sec. 5).
//  classify: inside -> Off; a front face within the cage diagonal -> Vigilant; else Sleeping
//            (thesis sec. 6.1's relevant samples; the 2021 paper's states, sec. 6).
//  start:    a probe that entered a scrolled volume starts over: no offset, no history (its
//            fixed rays are traced after this, for relocation and classification).
#include "common/field_update.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) readonly buffer Rays {
  ProbeRay rays[];
};

void main() {
  uint probe, local;
  if (!field_item(probe, local)) return;
  if (pc.mode == kProbeModeStart) {
    probe_states[probe].offset = vec3(0.0);
    probe_states[probe].flags = kProbeResetHistory;
    return;
  }
  const uint n = field.fixed_rays;
  const uint first = probe * rays_per_probe_total();
  uint backfaces = 0u;
  float closest_back = kFloatMax, closest_front = kFloatMax;
  vec3 back_direction = vec3(0.0), front_direction = vec3(0.0);
  for (uint r = 0u; r < n; ++r) {
    const float encoded = rays[first + r].distance;
    if (ray_missed(encoded)) continue;
    const float distance = ray_distance(encoded);
    if (!ray_hit_back_face(encoded)) {
      if (distance < closest_front) {
        closest_front = distance;
        front_direction = probe_ray_direction(r);
      }
    } else {
      ++backfaces;
      if (distance < closest_back) {
        closest_back = distance;
        back_direction = probe_ray_direction(r);
      }
    }
  }
  const bool inside = float(backfaces) > field.backface_threshold * float(n);

  if (pc.mode == kProbeModeRelocate) {
    const float min_spacing = min(field_grid.spacing.x, min(field_grid.spacing.y, field_grid.spacing.z));
    vec3 offset = probe_states[probe].offset;
    if (inside) {
      // Through the closest back face, and a little further so the face is behind us.
      offset += back_direction * (closest_back + 0.05 * min_spacing);
    } else if (closest_front < field_grid.min_frontface_distance) {
      offset -= front_direction * (field_grid.min_frontface_distance - closest_front);
    }
    const vec3 limit = field.probe_offset_limit * field_grid.spacing;
    probe_states[probe].offset = clamp(offset, -limit, limit);
    probe_states[probe].flags |= kProbeResetHistory;  // it moved: its history is elsewhere
  } else {
    const float reach = length(field_grid.spacing);  // the cage diagonal (thesis eq. 6.2's r)
    const uint state = inside ? kProbeOff
                              : (closest_front <= reach ? kProbeVigilant : kProbeSleeping);
    probe_states[probe].flags =
        (probe_states[probe].flags & ~kProbeStateMask) | (state << kProbeStateShift);
  }
}
