// What every field-update kernel shares: its push constants and the probe list it works on.
// Invocation i handles item i % per_probe of probe list[(list_start + i / per_probe) % size].
#ifndef DDGI_COMMON_FIELD_UPDATE_GLSL
#define DDGI_COMMON_FIELD_UPDATE_GLSL

#include "common/dispatch.glsl"
#include "common/field.glsl"

layout(push_constant, scalar) uniform Push { FieldDispatch pc; };
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingProbeList, scalar) readonly buffer
    ProbeList {
  uint probe_list[];
};

// --- ProbeRay::distance (shared/field_data.h) ---------------------------------------------
float encode_ray_distance(bool hit, bool front_face, float t) {
  if (!hit) return uintBitsToFloat(0x7f800000u);  // +infinity
  return front_face ? t : uintBitsToFloat(floatBitsToUint(t) | 0x80000000u);
}
bool ray_missed(float d) { return isinf(d); }
bool ray_hit_back_face(float d) { return (floatBitsToUint(d) & 0x80000000u) != 0u; }
// Hit distance; max_ray_distance on a miss.
float ray_distance(float d) { return min(abs(d), field.max_ray_distance); }

// The probe at entry `entry` of this dispatch's window of the probe list, and the entry's index
// in the list. Selects the probe's volume (`field`).
uint window_probe(uint entry, out uint list_index) {
  list_index = (pc.list_start + entry) % pc.list_size;
  const uint probe = probe_list[list_index];
  select_probe_volume(probe);
  return probe;
}

// False past the end of the dispatch. Selects the probe's volume (`field`).
bool field_item(out uint probe, out uint local) {
  const uint id = linear_invocation(pc.row_width);
  probe = 0u;
  local = 0u;
  if (id >= pc.count) return false;
  uint list_index;
  probe = window_probe(id / pc.per_probe, list_index);
  local = id % pc.per_probe;
  return true;
}

// Adaptive rays (docs/adaptive-rays.md): whether an update's lighting passes take the probe at
// entry `list_index` of the probe list. Every probe when the dispatch is not adaptive; else
// hot probes, probes without history and the maintenance slice. The trace and the blend ask
// the same question of the same flags (the trace does not write them), so they agree.
bool probe_lit_this_update(uint probe, uint list_index) {
  if (pc.skip_settled == 0u) return true;
  const uint flags = probe_states[probe].flags;
  if ((flags & (kProbeResetHistory | kProbeHeatMask)) != 0u) return true;
  const uint from_start = (list_index + pc.list_size - field.maintenance_start) % pc.list_size;
  return from_start < field.maintenance_count;
}

// field_item() for the lighting passes: also false for a probe this update leaves settled.
bool field_lit_item(out uint probe, out uint local) {
  if (!field_item(probe, local)) return false;
  const uint id = linear_invocation(pc.row_width);
  return probe_lit_this_update(probe, (pc.list_start + id / pc.per_probe) % pc.list_size);
}

#endif
