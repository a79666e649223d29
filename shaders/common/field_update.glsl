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

// False past the end of the dispatch.
bool field_item(out uint probe, out uint local) {
  const uint id = linear_invocation(pc.row_width);
  probe = 0u;
  local = 0u;
  if (id >= pc.count) return false;
  probe = probe_list[(pc.list_start + id / pc.per_probe) % pc.list_size];
  local = id % pc.per_probe;
  return true;
}

#endif
