#version 460
#extension GL_GOOGLE_include_directive : require
// Shadow field update, last pass: copies each octahedral map's edge texels into its one-texel
// border (mirrored along each edge, opposite corners at the corners), in the moments atlas and
// every light group of the visibility atlas, so bilinear lookups near an edge blend with the
// texels that are its neighbours on the sphere.
#define DDGI_SHADOW_FIELD_SET 2
#include "common/dispatch.glsl"
#include "gi/shadow_field.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(push_constant, scalar) uniform Push { ShadowDispatch pc; };
layout(set = kShadowUpdateSet, binding = kShadowUpdateBindingVisibilityOut,
       rgba32f) uniform image2D visibility_out;
layout(set = kShadowUpdateSet, binding = kShadowUpdateBindingMomentsOut,
       rgba32f) uniform image2D moments_out;

// Border texel b (0 <= b < 4 * (n + 1)) of an n x n map: where it goes and where it copies
// from, relative to the map's first interior texel. Edges first (top, bottom, left, right),
// then the four corners.
void border_texel(uint b, int n, out ivec2 dst, out ivec2 src) {
  const int i = int(b);
  const int edge = i / n;
  const int k = i % n;
  if (edge == 0) {
    dst = ivec2(k, -1);
    src = ivec2(n - 1 - k, 0);
  } else if (edge == 1) {
    dst = ivec2(k, n);
    src = ivec2(n - 1 - k, n - 1);
  } else if (edge == 2) {
    dst = ivec2(-1, k);
    src = ivec2(0, n - 1 - k);
  } else if (edge == 3) {
    dst = ivec2(n, k);
    src = ivec2(n - 1, n - 1 - k);
  } else {
    const int corner = i - 4 * n;
    dst = ivec2((corner & 1) == 0 ? -1 : n, corner < 2 ? -1 : n);
    src = ivec2((corner & 1) == 0 ? n - 1 : 0, corner < 2 ? n - 1 : 0);
  }
}

void main() {
  const uint id = linear_invocation(pc.row_width);
  if (id >= pc.count) return;
  const uint probe = id / pc.per_probe;
  ivec2 dst, src;
  border_texel(id % pc.per_probe, int(shadow.texels), dst, src);
  const ivec2 moments = shadow_map_origin(probe, 0u);
  imageStore(moments_out, moments + dst, imageLoad(moments_out, moments + src));
  const uint groups = (shadow.light_count + kShadowLightsPerGroup - 1u) / kShadowLightsPerGroup;
  for (uint g = 0u; g < groups; ++g) {
    const ivec2 base = shadow_map_origin(probe, g);
    imageStore(visibility_out, base + dst, imageLoad(visibility_out, base + src));
  }
}
