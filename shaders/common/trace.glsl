// One tracing interface, two backends. Kernels call trace_closest / trace_transmittance and
// use DDGI_INVOCATION_ID; the build compiles each kernel twice:
//   DDGI_BACKEND_QUERY:    compute shader with GL_EXT_ray_query
//   DDGI_BACKEND_PIPELINE: ray-generation shader with GL_EXT_ray_tracing, using the shared
//                          hit/miss shaders in shaders/common/*.r{chit,ahit,miss}
// Candidate hits (alpha mask, thin glass) are judged by the same functions in both.
#ifndef DDGI_COMMON_TRACE_GLSL
#define DDGI_COMMON_TRACE_GLSL

#if defined(DDGI_BACKEND_QUERY)
#extension GL_EXT_ray_query : require
#elif defined(DDGI_BACKEND_PIPELINE)
#extension GL_EXT_ray_tracing : require
#else
#error "define DDGI_BACKEND_QUERY or DDGI_BACKEND_PIPELINE"
#endif

#include "common/scene.glsl"
#include "common/ray_payloads.glsl"

#if defined(DDGI_BACKEND_QUERY)

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
#define DDGI_INVOCATION_ID gl_GlobalInvocationID

vec3 trace_transmittance(vec3 origin, vec3 direction, float tmin, float tmax);
Hit with_glass(Hit hit, GlassLayers glass, vec3 origin, vec3 direction, float tmin, float tmax);

Hit trace_closest(vec3 origin, vec3 direction, float tmin, float tmax) {
  GlassLayers glass;
  glass.count = 0u;
  rayQueryEXT query;
  rayQueryInitializeEXT(query, scene_tlas, gl_RayFlagsNoneEXT, 0xFF, origin, tmin, direction,
                        tmax);
  while (rayQueryProceedEXT(query)) {
    if (rayQueryGetIntersectionTypeEXT(query, false) ==
        gl_RayQueryCandidateIntersectionTriangleEXT) {
      vec3 passed;
      if (candidate_is_surface(rayQueryGetIntersectionInstanceCustomIndexEXT(query, false),
                               rayQueryGetIntersectionGeometryIndexEXT(query, false),
                               rayQueryGetIntersectionPrimitiveIndexEXT(query, false),
                               rayQueryGetIntersectionBarycentricsEXT(query, false), passed)) {
        rayQueryConfirmIntersectionEXT(query);
      } else if (any(notEqual(passed, vec3(1.0)))) {
        add_glass_layer(glass, rayQueryGetIntersectionTEXT(query, false), passed);
      }
    }
  }
  Hit hit = miss_hit();
  if (rayQueryGetIntersectionTypeEXT(query, true) != gl_RayQueryCommittedIntersectionNoneEXT) {
    hit.t = rayQueryGetIntersectionTEXT(query, true);
    hit.instance = rayQueryGetIntersectionInstanceCustomIndexEXT(query, true);
    hit.geometry = rayQueryGetIntersectionGeometryIndexEXT(query, true);
    hit.primitive = rayQueryGetIntersectionPrimitiveIndexEXT(query, true);
    hit.barycentrics = rayQueryGetIntersectionBarycentricsEXT(query, true);
  }
  return with_glass(hit, glass, origin, direction, tmin, tmax);
}

vec3 trace_transmittance(vec3 origin, vec3 direction, float tmin, float tmax) {
  vec3 transmittance = vec3(1.0);
  rayQueryEXT query;
  rayQueryInitializeEXT(query, scene_tlas, gl_RayFlagsTerminateOnFirstHitEXT, 0xFF, origin, tmin,
                        direction, tmax);
  while (rayQueryProceedEXT(query)) {
    if (rayQueryGetIntersectionTypeEXT(query, false) ==
        gl_RayQueryCandidateIntersectionTriangleEXT) {
      const vec3 f = candidate_transmittance(
          rayQueryGetIntersectionInstanceCustomIndexEXT(query, false),
          rayQueryGetIntersectionGeometryIndexEXT(query, false),
          rayQueryGetIntersectionPrimitiveIndexEXT(query, false),
          rayQueryGetIntersectionBarycentricsEXT(query, false));
      if (all(equal(f, vec3(0.0)))) {
        rayQueryConfirmIntersectionEXT(query);
      } else {
        transmittance *= f;
      }
    }
  }
  if (rayQueryGetIntersectionTypeEXT(query, true) != gl_RayQueryCommittedIntersectionNoneEXT) {
    return vec3(0.0);
  }
  return transmittance;
}

#else  // DDGI_BACKEND_PIPELINE

#define DDGI_INVOCATION_ID gl_LaunchIDEXT
layout(location = kPayloadClosest) rayPayloadEXT ClosestPayload closest_payload;
layout(location = kPayloadShadow) rayPayloadEXT ShadowPayload shadow_payload;

vec3 trace_transmittance(vec3 origin, vec3 direction, float tmin, float tmax);
Hit with_glass(Hit hit, GlassLayers glass, vec3 origin, vec3 direction, float tmin, float tmax);

Hit trace_closest(vec3 origin, vec3 direction, float tmin, float tmax) {
  closest_payload.t = -1.0;
  closest_payload.glass.count = 0u;
  // SBT offset = ray type, stride 0: every geometry uses the same hit group.
  traceRayEXT(scene_tlas, gl_RayFlagsNoneEXT, 0xFF, kRayTypeClosest, 0, kRayTypeClosest, origin,
              tmin, direction, tmax, kPayloadClosest);
  Hit hit = miss_hit();
  if (closest_payload.t >= 0.0) {
    hit.t = closest_payload.t;
    hit.instance = closest_payload.instance;
    hit.geometry = closest_payload.geometry;
    hit.primitive = closest_payload.primitive;
    hit.barycentrics = closest_payload.barycentrics;
  }
  return with_glass(hit, closest_payload.glass, origin, direction, tmin, tmax);
}

vec3 trace_transmittance(vec3 origin, vec3 direction, float tmin, float tmax) {
  shadow_payload.transmittance = vec3(1.0);
  traceRayEXT(scene_tlas, gl_RayFlagsTerminateOnFirstHitEXT, 0xFF, kRayTypeShadow, 0,
              kRayTypeShadow, origin, tmin, direction, tmax, kPayloadShadow);
  return shadow_payload.transmittance;
}

#endif

// `hit` with the transmittance of the glass in front of it (of all glass before tmax on a miss):
// from the layers its own traversal saw, or, when more were seen than it keeps, from an exact
// transmittance ray (rare).
Hit with_glass(Hit hit, GlassLayers glass, vec3 origin, vec3 direction, float tmin, float tmax) {
  const float end = hit.t < 0.0 ? tmax : hit.t;
  if (!glass_before(glass, end, hit.transmittance)) {
    hit.transmittance = trace_transmittance(origin, direction, tmin, end);
  }
  return hit;
}

#endif
