// Sampling of emissive triangles (the table GpuScene builds, shared/scene_data.h): by area for
// the path tracer, by solid angle for the frame's and probe rays' next-event estimation.
#ifndef DDGI_COMMON_EMITTERS_GLSL
#define DDGI_COMMON_EMITTERS_GLSL

#include "common/scene.glsl"
#include "common/sampling.glsl"
#include "common/spherical_triangle.glsl"

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

// What emitter `e` sends from its point at barycentrics `bary` (`position`) towards
// `receiver`, and its face normal turned that way.
vec3 emitted_towards(GpuEmitter e, vec2 bary, vec3 position, vec3 receiver, out vec3 normal) {
  const GpuGeometry geo = scene_geometries[e.geometry];
  const GpuMaterial m = scene_materials[geo.material];
  const bool front = dot(e.normal, receiver - position) > 0.0;
  normal = front ? e.normal : -e.normal;
  if (!front && (geo.flags & kGeometryDoubleSided) == 0u) return vec3(0.0);
  vec3 radiance = e.emission;
  if (m.emissive_texture >= 0) {
    const vec2 uv = interpolate_uv(triangle_vertices(geo, e.primitive), bary);
    radiance *= sample_texture(m.emissive_texture, uv).rgb;
  }
  // A cut-out texel is no surface: it emits nothing (closest-hit rays pass it too).
  if ((geo.flags & kGeometryAlphaMask) != 0u &&
      material_alpha(geo, e.primitive, bary) < m.alpha_cutoff) {
    return vec3(0.0);
  }
  return radiance;
}

// A point on an emitter, as seen from `receiver`, chosen by area (the path tracer's light
// sampling, whose MIS weights use this density). Needs scene.emitter_count > 0.
EmitterSample sample_emitter(vec3 receiver, float u_pick, vec2 u_point) {
  const GpuEmitter e = scene_emitters[pick_emitter(u_pick)];
  const vec2 bary = sample_triangle(u_point);
  EmitterSample s;
  s.position = e.p0 * (1.0 - bary.x - bary.y) + e.p1 * bary.x + e.p2 * bary.y;
  s.area_pdf = emitter_area_pdf(e.emission);
  s.radiance = emitted_towards(e, bary, s.position, receiver, s.normal);
  return s;
}

// Barycentrics (b1, b2) of a point `p` in the plane of emitter e, clamped into the triangle.
vec2 emitter_barycentrics(GpuEmitter e, vec3 p) {
  const vec3 e1 = e.p1 - e.p0, e2 = e.p2 - e.p0, d = p - e.p0;
  const float d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
  const float denominator = d11 * d22 - d12 * d12;
  if (!(denominator > 0.0)) return vec2(0.0);
  const float b1 = (d22 * dot(d, e1) - d12 * dot(d, e2)) / denominator;
  const float b2 = (d11 * dot(d, e2) - d12 * dot(d, e1)) / denominator;
  const vec2 b = clamp(vec2(b1, b2), 0.0, 1.0);
  return b.x + b.y > 1.0 ? b / (b.x + b.y) : b;
}

// Below this solid angle (steradians) an emitter triangle is sampled by area: the spherical
// triangle's angles lose precision in single precision, and a triangle that small subtends
// nearly the same 1 / distance^2 everywhere, so area sampling is as good there.
const float kMinEmitterSolidAngle = 1e-3;

struct EmitterDirection {
  vec3 position;  // the point sampled on the emitter
  vec3 weight;    // emitted radiance towards the receiver over the sample's solid-angle density
};

// A point on an emitter seen from `receiver`, for next-event estimation without MIS
// (common/emitter_direct.glsl): the triangle picked as by area (area x luminance), then a
// direction uniform in the solid angle it subtends, so the weight stays bounded by radiance x
// solid angle however close the receiver is; small triangles are sampled by area. Needs
// scene.emitter_count > 0.
EmitterDirection sample_emitter_direction(vec3 receiver, float u_pick, vec2 u) {
  const GpuEmitter e = scene_emitters[pick_emitter(u_pick)];
  const float pick = e.area * emitter_area_pdf(e.emission);  // probability of this triangle
  const SphericalTriangle t = spherical_triangle(
      normalize(e.p0 - receiver), normalize(e.p1 - receiver), normalize(e.p2 - receiver));
  EmitterDirection result;
  float inverse_density;  // 1 / (the sample's density per unit solid angle)
  vec2 bary;
  if (t.solid_angle > kMinEmitterSolidAngle) {
    const vec3 direction = sample_spherical_triangle(t, u);
    const float distance = dot(e.p0 - receiver, e.normal) / dot(direction, e.normal);
    result.position = receiver + distance * direction;
    bary = emitter_barycentrics(e, result.position);
    // A direction along the plane (rounding at the triangle's rim) reaches no point of it.
    inverse_density = distance > 0.0 && distance < kFloatMax ? t.solid_angle / pick : 0.0;
  } else {
    bary = sample_triangle(u);
    result.position = e.p0 * (1.0 - bary.x - bary.y) + e.p1 * bary.x + e.p2 * bary.y;
    const vec3 to_emitter = result.position - receiver;
    const float d2 = dot(to_emitter, to_emitter);
    inverse_density = e.area * abs(dot(e.normal, to_emitter)) * inversesqrt(d2) / (d2 * pick);
  }
  vec3 normal;  // not needed here: the receiver's cosine is the caller's
  const vec3 radiance = emitted_towards(e, bary, result.position, receiver, normal);
  result.weight = inverse_density > 0.0 ? radiance * inverse_density : vec3(0.0);
  return result;
}

#endif
