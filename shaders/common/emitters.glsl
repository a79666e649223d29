// Area sampling of emissive triangles (the table GpuScene builds, shared/scene_data.h).
#ifndef DDGI_COMMON_EMITTERS_GLSL
#define DDGI_COMMON_EMITTERS_GLSL

#include "common/scene.glsl"
#include "common/sampling.glsl"

// The density, per unit area, with which emitter sampling picks a point on a surface whose
// emissive factor is `emissive`. It does not depend on the triangle: triangles are chosen in
// proportion to area x luminance and points uniformly on them.
float emitter_area_pdf(vec3 emissive) {
  return scene.emitter_total_weight > 0.0 ? luminance(emissive) / scene.emitter_total_weight
                                          : 0.0;
}

// The first emitter whose cumulative probability exceeds u.
uint pick_emitter(float u) {
  uint lo = 0u;
  uint hi = scene.emitter_count - 1u;
  while (lo < hi) {
    const uint mid = (lo + hi) / 2u;
    if (scene_emitters[mid].cdf > u) {
      hi = mid;
    } else {
      lo = mid + 1u;
    }
  }
  return lo;
}

struct EmitterSample {
  vec3 position;
  vec3 normal;      // face normal, turned towards the receiving point
  vec3 radiance;    // emitted towards the receiving point (0 from a back face or a cut-out)
  float area_pdf;
};

// A point on an emitter, as seen from `receiver`. Needs scene.emitter_count > 0.
EmitterSample sample_emitter(vec3 receiver, float u_pick, vec2 u_point) {
  const GpuEmitter e = scene_emitters[pick_emitter(u_pick)];
  const vec2 bary = sample_triangle(u_point);
  EmitterSample s;
  s.position = e.p0 * (1.0 - bary.x - bary.y) + e.p1 * bary.x + e.p2 * bary.y;
  s.area_pdf = emitter_area_pdf(e.emission);

  const GpuGeometry geo = scene_geometries[e.geometry];
  const GpuMaterial m = scene_materials[geo.material];
  const bool front = dot(e.normal, receiver - s.position) > 0.0;
  s.normal = front ? e.normal : -e.normal;
  s.radiance = e.emission;
  if (!front && (geo.flags & kGeometryDoubleSided) == 0u) s.radiance = vec3(0.0);
  if (m.emissive_texture >= 0) {
    const vec2 uv = interpolate_uv(triangle_vertices(geo, e.primitive), bary);
    s.radiance *= sample_texture(m.emissive_texture, uv).rgb;
  }
  // A cut-out texel is no surface: it emits nothing (closest-hit rays pass it too).
  if ((geo.flags & kGeometryAlphaMask) != 0u &&
      material_alpha(geo, e.primitive, bary) < m.alpha_cutoff) {
    s.radiance = vec3(0.0);
  }
  return s;
}

#endif
