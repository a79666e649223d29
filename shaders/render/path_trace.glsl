#version 460
#extension GL_GOOGLE_include_directive : require
// Reference path tracer: progressive, seeded, unbiased up to the bounce limit. Lambertian
// surfaces; next-event estimation for punctual lights and emissive triangles, combined with
// BSDF-sampled emitter hits by multiple importance sampling; environment light on misses;
// Russian roulette. See docs/reference-path-tracer.md.
#include "common/lights.glsl"
#include "common/emitters.glsl"
#include "common/sampling.glsl"
#include "shared/path_trace_data.h"

layout(push_constant, scalar) uniform Push { PathTraceConstants pc; };
layout(set = kPathTraceSet, binding = kPathTraceBindingRadiance, scalar) buffer Radiance {
  vec4 radiance[];
};

// One path's radiance, split by how the light reached the camera.
struct PathRadiance {
  vec3 seen;      // emission (and environment) seen directly by the camera
  vec3 punctual;  // punctual lights at the first visible surface
  vec3 direct;    // emitters and environment at the first visible surface
  vec3 indirect;  // light that bounced at least once before the first visible surface
};

// Adds emission found at the end of path segment `segment` (0: the camera ray).
void add_emission(inout PathRadiance r, uint segment, vec3 value) {
  if (segment == 0u) {
    r.seen += value;
  } else if (segment == 1u) {
    r.direct += value;
  } else {
    r.indirect += value;
  }
}

// Next-event estimation towards one point on an emitter, MIS-weighted against BSDF sampling.
// Returns the reflected radiance before the path throughput.
vec3 emitter_lighting(Surface s, vec3 origin, inout Rng rng) {
  const float u_pick = rng_next(rng);
  const vec2 u_point = vec2(rng_next(rng), rng_next(rng));
  if (scene.emitter_count == 0u) return vec3(0.0);
  const EmitterSample e = sample_emitter(s.position, u_pick, u_point);
  const vec3 to_light = e.position - s.position;
  const float d2 = dot(to_light, to_light);
  if (!(d2 > 0.0) || !(e.area_pdf > 0.0) || all(equal(e.radiance, vec3(0.0)))) return vec3(0.0);
  const vec3 wi = to_light * inversesqrt(d2);
  const float cos_surface = dot(s.normal, wi);
  const float cos_light = dot(e.normal, -wi);
  if (cos_surface <= 0.0 || dot(s.geometric_normal, wi) <= 0.0 || cos_light <= 0.0) {
    return vec3(0.0);
  }
  // Aim just off the emitter, on the receiver's side, so that it does not shadow itself.
  const vec3 target = offset_ray_origin(e.position, e.normal);
  const vec3 ray = target - origin;
  const float distance = length(ray);
  const vec3 visibility = trace_transmittance(origin, ray / distance, 0.0, distance);
  if (all(equal(visibility, vec3(0.0)))) return vec3(0.0);
  const float light_pdf = e.area_pdf * d2 / cos_light;  // per unit solid angle
  const float bsdf_pdf = cos_surface * kInvPi;
  const float weight = power_heuristic(light_pdf, bsdf_pdf);
  return s.albedo * kInvPi * e.radiance * visibility * (cos_surface * weight / light_pdf);
}

PathRadiance trace_path(vec3 origin, vec3 direction, inout Rng rng) {
  PathRadiance r;
  r.seen = r.punctual = r.direct = r.indirect = vec3(0.0);
  // Direct-only views need nothing past the first bounce's hit.
  const bool direct_view = pc.view == kPathTraceDirect || pc.view == kPathTracePunctualDirect;
  const uint max_bounces = direct_view ? min(pc.max_bounces, 1u) : pc.max_bounces;
  const bool sample_emitters = pc.view != kPathTracePunctualDirect && scene.emitter_count > 0u;
  vec3 throughput = vec3(1.0);
  float tmin = pc.tmin;
  float bsdf_pdf = 0.0;  // of the segment being traced (0 for the camera ray)

  for (uint segment = 0u;; ++segment) {
    const Hit hit = trace_closest(origin, direction, tmin, kFloatMax);
    throughput *= hit.transmittance;
    if (hit.t < 0.0) {
      add_emission(r, segment, throughput * environment_radiance(direction));
      break;
    }
    const Surface s = surface_at(hit, direction);
    if (any(greaterThan(s.emission, vec3(0.0)))) {
      float weight = 1.0;
      if (segment > 0u && sample_emitters) {
        const float cos_light = abs(dot(s.geometric_normal, direction));
        const float light_pdf =
            emitter_area_pdf(scene_materials[s.material].emissive) * hit.t * hit.t /
            max(cos_light, 1e-12);
        weight = power_heuristic(bsdf_pdf, light_pdf);
      }
      add_emission(r, segment, throughput * s.emission * weight);
    }
    if (segment >= max_bounces) break;

    // Light arriving at this vertex straight from a source.
    const vec3 origin_out = offset_ray_origin(s.position, s.geometric_normal);
    const vec3 punctual = throughput * direct_lighting(s, true, rng);
    if (segment == 0u) {
      r.punctual += punctual;
      if (pc.view == kPathTracePunctualDirect) break;  // nothing else counts in this view
    } else {
      r.indirect += punctual;
    }
    if (sample_emitters) {
      const vec3 area = throughput * emitter_lighting(s, origin_out, rng);
      if (segment == 0u) {
        r.direct += area;
      } else {
        r.indirect += area;
      }
    }

    // Continue along a cosine-weighted direction: Lambert's f cos / pdf is the albedo.
    const vec2 u = vec2(rng_next(rng), rng_next(rng));
    direction = sample_cosine_hemisphere(s.normal, u);
    bsdf_pdf = dot(s.normal, direction) * kInvPi;
    if (dot(direction, s.geometric_normal) <= 0.0 || !(bsdf_pdf > 0.0)) break;
    throughput *= s.albedo;
    if (segment + 1u >= pc.roulette_start) {
      const float survive = min(max_component(throughput), 1.0);
      if (!(rng_next(rng) < survive)) break;
      throughput /= survive;
    }
    origin = origin_out;
    tmin = 0.0;
  }
  r.seen = sanitize_radiance(r.seen);
  r.punctual = sanitize_radiance(r.punctual);
  r.direct = sanitize_radiance(r.direct);
  r.indirect = sanitize_radiance(r.indirect);
  return r;
}

vec3 view_of(PathRadiance r) {
  switch (pc.view) {
    case kPathTraceDirect: return (r.seen + r.punctual) + r.direct;
    case kPathTraceIndirect: return r.indirect;
    case kPathTracePunctualDirect: return r.seen + r.punctual;
    case kPathTraceFieldIndirect: return r.direct + r.indirect;
    default: return ((r.seen + r.punctual) + r.direct) + r.indirect;
  }
}

void main() {
  const uvec2 pixel = DDGI_INVOCATION_ID.xy;
  if (pixel.x >= pc.width || pixel.y >= pc.height) return;
  const uint index = pixel.y * pc.width + pixel.x;
  vec3 sum = vec3(0.0);
  for (uint i = 0u; i < pc.sample_count; ++i) {
    // Each sample has its own sequence: images do not depend on how samples are batched.
    Rng rng = rng_seed(index, pc.first_sample + i, pc.seed);
    const vec2 jitter = vec2(rng_next(rng), rng_next(rng));
    const vec2 offset = pc.jitter != 0u ? jitter : vec2(0.5);
    const vec2 ndc = (vec2(pixel) + offset) / vec2(pc.width, pc.height) * 2.0 - 1.0;
    const vec3 direction =
        normalize(pc.camera_forward + ndc.x * pc.camera_right - ndc.y * pc.camera_up);
    sum += sanitize_radiance(view_of(trace_path(pc.camera_position, direction, rng)));
  }
  const float total = float(pc.first_sample + pc.sample_count);
  vec3 mean = sanitize_radiance(sum) / total;
  if (pc.first_sample > 0u) mean += radiance[index].rgb * (float(pc.first_sample) / total);
  radiance[index] = vec4(mean, 1.0);
}
