#version 460
#extension GL_GOOGLE_include_directive : require
// SH field update, pass 2: one workgroup per probe projects the radiance of its blended rays on
// the nine SH functions (Monte Carlo: the rays are a rotated spherical Fibonacci set, uniform
// over the sphere, so each carries 4 pi / n of solid angle) and blends the result into the
// probe's coefficients with the field's hysteresis. Each invocation sums a strided share of the
// rays; nine invocations then add the shares in a fixed order, so both tracing backends give
// the same coefficients from the same rays.
#include "common/field_update.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(set = kFieldUpdateSet, binding = kFieldUpdateBindingRays, scalar) readonly buffer Rays {
  ProbeRay rays[];
};

// One share per invocation; the workgroup is kProbeWorkgroup (64) of irradiance_field.cpp.
const uint kMaxInvocations = 64u;
shared vec3 shares[kMaxInvocations * kShCoefficients];

void main() {
  const uint slot = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
  if (slot >= pc.count) return;  // the whole workgroup
  const uint probe = probe_list[(pc.list_start + slot) % pc.list_size];
  select_probe_volume(probe);
  const bool reset = (probe_states[probe].flags & kProbeResetHistory) != 0u;
  const uint first = probe * rays_per_probe_total() + field.fixed_rays;
  const uint n = field.rays_per_probe;
  const uint invocations = min(gl_WorkGroupSize.x, kMaxInvocations);
  const uint me = gl_LocalInvocationIndex;

  vec3 sums[9];
  for (uint k = 0u; k < kShCoefficients; ++k) sums[k] = vec3(0.0);
  if (me < invocations) {
    for (uint i = me; i < n; i += invocations) {
      float y[9];
      sh_basis(probe_ray_direction(field.fixed_rays + i), y);
      const vec3 radiance = rays[first + i].radiance;
      for (uint k = 0u; k < kShCoefficients; ++k) sums[k] += y[k] * radiance;
    }
    for (uint k = 0u; k < kShCoefficients; ++k) shares[me * kShCoefficients + k] = sums[k];
  }
  barrier();
  if (me < kShCoefficients) {
    vec3 total = vec3(0.0);
    for (uint t = 0u; t < invocations; ++t) total += shares[t * kShCoefficients + me];
    const vec3 estimate = total * (4.0 * kPi / float(n));
    const float h = reset ? 0.0 : field.hysteresis;
    sh_probes[probe].coefficients[me] = mix(estimate, sh_probes[probe].coefficients[me], h);
  }
  // Every invocation read the reset flag before the barrier; no other workgroup blends this probe.
  if (me == 0u) probe_states[probe].flags &= ~kProbeResetHistory;
}
