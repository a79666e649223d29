#version 460
#extension GL_GOOGLE_include_directive : require
// Split field update, pass 5: copies each octahedral map's edge texels into its one-texel
// border (border_texel in gi/field_blend.glsl). Ends the update: clears the probes'
// reset-history flags.
#include "gi/field_blend.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

void main() {
  uint probe, b;
  if (!field_item(probe, b)) return;
  copy_border_texel(probe, b);
  if (b == 0u) probe_states[probe].flags &= ~kProbeResetHistory;
}
