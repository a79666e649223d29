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

// False past the end of the dispatch. Selects the probe's volume (`field`).
bool field_item(out uint probe, out uint local) {
  const uint id = linear_invocation(pc.row_width);
  probe = 0u;
  local = 0u;
  if (id >= pc.count) return false;
  probe = probe_list[(pc.list_start + id / pc.per_probe) % pc.list_size];
  local = id % pc.per_probe;
  select_probe_volume(probe);
  return true;
}

#endif
