#version 460
#extension GL_GOOGLE_include_directive : require
// The shadow field at given points (tests, ddgi-shadow-eval): its soft visibility per kept light
// and its AO, next to what traced rays say there (the ground truth the field approximates).
#define DDGI_SHADOW_FIELD_SET 2
#include "common/lights.glsl"
#include "common/dispatch.glsl"
#include "gi/shadow_field.glsl"
#include "gi/shadow_rays.glsl"

layout(push_constant, scalar) uniform Push { ShadowDispatch pc; };
layout(set = kShadowQuerySet, binding = kShadowQueryBindingQueries, scalar) readonly buffer Queries {
  ShadowQuery queries[];
};
layout(set = kShadowQuerySet, binding = kShadowQueryBindingAnswers, scalar) writeonly buffer Answers {
  ShadowAnswer answers[];
};

void main() {
  const uint id = linear_invocation(pc.row_width);
  if (id >= pc.count) return;
  const ShadowQuery q = queries[id];
  const ShadowSample shadowing = sample_shadow_field(q.position, q.normal, q.to_viewer);

  ShadowAnswer a;
  a.field_visibility = shadowing.visibility;
  a.field_ao = shadowing.ao;
  a.weight_sum = shadowing.weight_sum;
  a.pad0 = 0.0;
  Rng rng = rng_seed(id, q.seed, 0x2545f491u);
  const uint lights = min(scene.light_count, kShadowMaxLights);
  for (uint g = 0u; g < kShadowMaxGroups; ++g) a.traced_visibility[g] = vec4(1.0);
  for (uint light = 0u; light < lights; ++light) {
    const uint samples = scene_lights[light].radius > 0.0 ? max(q.traced_samples, 1u) : 1u;
    float sum = 0.0;
    for (uint s = 0u; s < samples; ++s) {
      // Stratified over the disc's radius so few samples already give a smooth penumbra.
      const vec2 jitter = vec2((float(s) + rng_next(rng)) / float(samples), rng_next(rng));
      sum += shadow_ray_visibility(q.position, q.normal, scene_lights[light], jitter);
    }
    a.traced_visibility[light / kShadowLightsPerGroup][light % kShadowLightsPerGroup] =
        sum / float(samples);
  }
  float open = 0.0;
  const uint ao_samples = max(q.ao_samples, 1u);
  for (uint s = 0u; s < ao_samples; ++s) {
    const vec2 u = vec2((float(s) + rng_next(rng)) / float(ao_samples), rng_next(rng));
    open += ao_ray_open(q.position, q.normal, u, shadow.ao_distance);
  }
  a.traced_ao = open / float(ao_samples);
  answers[id] = a;
}
