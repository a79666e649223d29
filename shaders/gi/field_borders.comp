#version 460
#extension GL_GOOGLE_include_directive : require
// Field update, pass 5: copies each octahedral map's edge texels into its one-texel border
// (mirrored along each edge, opposite corners at the corners) so bilinear lookups near an
// edge blend with the texels that are its neighbours on the sphere. Ends the update: clears
// the probes' reset-history flags.
#include "common/field_update.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingIrradianceOut, rgba32f) uniform image2D irradiance_out;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingDistanceOut, rg32f) uniform image2D distance_out;

// Border texel b (0 <= b < 4 * (n + 1)) of an n x n map: where it is and where it copies from,
// both relative to the map's first interior texel.
void border_texel(uint b, int n, out ivec2 dst, out ivec2 src) {
  const int i = int(b);
  if (i < n) {
    dst = ivec2(i, -1);
    src = ivec2(n - 1 - i, 0);
  } else if (i < 2 * n) {
    dst = ivec2(i - n, n);
    src = ivec2(n - 1 - (i - n), n - 1);
  } else if (i < 3 * n) {
    dst = ivec2(-1, i - 2 * n);
    src = ivec2(0, n - 1 - (i - 2 * n));
  } else if (i < 4 * n) {
    dst = ivec2(n, i - 3 * n);
    src = ivec2(n - 1, n - 1 - (i - 3 * n));
  } else {
    const int corner = i - 4 * n;
    dst = ivec2((corner & 1) == 0 ? -1 : n, corner < 2 ? -1 : n);
    src = ivec2((corner & 1) == 0 ? n - 1 : 0, corner < 2 ? n - 1 : 0);
  }
}

void main() {
  uint probe, b;
  if (!field_item(probe, b)) return;

  ivec2 dst, src;
  if (b < 4u * (field.irradiance_texels + 1u)) {
    border_texel(b, int(field.irradiance_texels), dst, src);
    const ivec2 base = ivec2(probe_tile_origin(probe, field.irradiance_texels) + kAtlasBorder);
    imageStore(irradiance_out, base + dst, imageLoad(irradiance_out, base + src));
  }
  if (b < 4u * (field.distance_texels + 1u)) {
    border_texel(b, int(field.distance_texels), dst, src);
    const ivec2 base = ivec2(probe_tile_origin(probe, field.distance_texels) + kAtlasBorder);
    imageStore(distance_out, base + dst, imageLoad(distance_out, base + src));
  }
  if (b == 0u) probe_states[probe].flags &= ~kProbeResetHistory;
}
