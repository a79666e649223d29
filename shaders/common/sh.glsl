// Real spherical harmonics of bands 0-2 (nine functions) and the irradiance they encode: the
// SH probe basis (DDISH-GI, Ikkala et al. 2022; Ramamoorthi and Hanrahan 2001 for the cosine
// lobe). A probe stores radiance coefficients L_lm = integral L(w) Y_lm(w) dw; irradiance is
// E(n) = sum_l A_l h_l sum_m L_lm Y_lm(n) with A_0 = pi, A_1 = 2pi/3, A_2 = pi/4 and a ringing
// window h_l. The field works in M = E / pi (field_data.h), so band l is scaled by A_l / pi h_l:
// 1, FieldConstants::sh_band1, ::sh_band2 (set by the server from sh_window).
// docs/sh-probes.md explains the ringing and the window. Mirrored for clients in
// proto/rpc/probe_field.h and web/probes.js.
#ifndef DDGI_COMMON_SH_GLSL
#define DDGI_COMMON_SH_GLSL

#include "shared/field_data.h"

const uint kShCoefficients = 9u;

// The nine basis functions at unit direction d, in the order l = 0; l = 1 (m = -1, 0, 1);
// l = 2 (m = -2 .. 2).
void sh_basis(vec3 d, out float y[9]) {
  y[0] = 0.282094792;
  y[1] = 0.488602512 * d.y;
  y[2] = 0.488602512 * d.z;
  y[3] = 0.488602512 * d.x;
  y[4] = 1.092548431 * d.x * d.y;
  y[5] = 1.092548431 * d.y * d.z;
  y[6] = 0.315391565 * (3.0 * d.z * d.z - 1.0);
  y[7] = 1.092548431 * d.x * d.z;
  y[8] = 0.546274215 * (d.x * d.x - d.y * d.y);
}

// M (= E / pi) around normal n from one probe's radiance coefficients; band 2 ringing can make
// it negative behind strong directional light, which is clamped.
vec3 sh_irradiance(ShProbe probe, vec3 n, float band1, float band2) {
  float y[9];
  sh_basis(n, y);
  vec3 m = probe.coefficients[0] * y[0];
  vec3 b1 = vec3(0.0), b2 = vec3(0.0);
  for (uint k = 1u; k < 4u; ++k) b1 += probe.coefficients[k] * y[k];
  for (uint k = 4u; k < 9u; ++k) b2 += probe.coefficients[k] * y[k];
  return max(m + band1 * b1 + band2 * b2, vec3(0.0));
}

#endif
