#include "rpc/probe_field.h"

#include <algorithm>
#include <cmath>

namespace ddgi {
namespace {

constexpr uint32_t kProbeOff = 3;  // shaders/shared/field_data.h

// ---- The few vector operations the shader uses, in float as the GPU computes them ----------
ProbeVec3 operator+(ProbeVec3 a, ProbeVec3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
ProbeVec3 operator-(ProbeVec3 a, ProbeVec3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
ProbeVec3 operator*(ProbeVec3 a, float s) {
  return {a.x * s, a.y * s, a.z * s};
}
float dot(ProbeVec3 a, ProbeVec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

ProbeVec3 safe_normalize(ProbeVec3 v, ProbeVec3 fallback) {
  const float length2 = dot(v, v);
  return length2 > 1e-30f && !std::isinf(length2) ? v * (1.0f / std::sqrt(length2)) : fallback;
}

float sign_not_zero(float v) {
  return v >= 0.0f ? 1.0f : -1.0f;
}

// [-1, 1]^2 coordinates of a unit direction (Cigolle et al. 2014), as math.glsl.
void octahedral_encode(ProbeVec3 n, float* u, float* v) {
  const float scale = 1.0f / (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z));
  const float px = n.x * scale, py = n.y * scale;
  if (n.z <= 0.0f) {
    *u = (1.0f - std::fabs(py)) * sign_not_zero(px);
    *v = (1.0f - std::fabs(px)) * sign_not_zero(py);
  } else {
    *u = px;
    *v = py;
  }
}

// A linear, clamp-to-edge texture read at normalized (s, t), as Vulkan defines it.
template <int Channels>
void bilinear(const std::vector<float>& texels, uint32_t width, uint32_t height, float s, float t,
              float out[Channels]) {
  const float u = s * float(width) - 0.5f, v = t * float(height) - 0.5f;
  const float fu = std::floor(u), fv = std::floor(v);
  const float a = u - fu, b = v - fv;
  const int x0 = int(fu), y0 = int(fv);
  auto at = [&](int x, int y, int c) {
    x = std::clamp(x, 0, int(width) - 1);
    y = std::clamp(y, 0, int(height) - 1);
    return texels[(size_t(y) * width + size_t(x)) * Channels + size_t(c)];
  };
  for (int c = 0; c < Channels; ++c) {
    out[c] = (1.0f - a) * (1.0f - b) * at(x0, y0, c) + a * (1.0f - b) * at(x0 + 1, y0, c) +
             (1.0f - a) * b * at(x0, y0 + 1, c) + a * b * at(x0 + 1, y0 + 1, c);
  }
}

// Normalized atlas coordinates of direction `d` in probe p's map (field.glsl, atlas_uv).
void atlas_uv(const ProbeField& f, uint32_t p, ProbeVec3 d, uint32_t texels, uint32_t width,
              uint32_t height, float* s, float* t) {
  float ou = 0.0f, ov = 0.0f;
  octahedral_encode(d, &ou, &ov);
  const uint32_t tile = texels + 2u * f.border_texels;
  const float origin_x = float((p % f.tiles_per_row) * tile);
  const float origin_y = float((p / f.tiles_per_row) * tile);
  *s = (origin_x + float(f.border_texels) + (ou * 0.5f + 0.5f) * float(texels)) / float(width);
  *t = (origin_y + float(f.border_texels) + (ov * 0.5f + 0.5f) * float(texels)) / float(height);
}

// M (= E / pi) around n from SH probe p's coefficients, as sh.glsl's sh_irradiance.
ProbeVec3 sh_irradiance(const ProbeField& f, uint32_t p, ProbeVec3 d) {
  const float y[9] = {0.282094792f,
                      0.488602512f * d.y,
                      0.488602512f * d.z,
                      0.488602512f * d.x,
                      1.092548431f * d.x * d.y,
                      1.092548431f * d.y * d.z,
                      0.315391565f * (3.0f * d.z * d.z - 1.0f),
                      1.092548431f * d.x * d.z,
                      0.546274215f * (d.x * d.x - d.y * d.y)};
  const float* c = &f.sh[size_t(p) * 27];
  float out[3];
  for (int ch = 0; ch < 3; ++ch) {
    float band1 = 0.0f, band2 = 0.0f;
    for (int k = 1; k < 4; ++k) band1 += c[k * 3 + ch] * y[k];
    for (int k = 4; k < 9; ++k) band2 += c[k * 3 + ch] * y[k];
    out[ch] =
        std::max(c[ch] * y[0] + f.sh_band_scales[1] * band1 + f.sh_band_scales[2] * band2, 0.0f);
  }
  return {out[0], out[1], out[2]};
}

// What the cage blends of probe p around n (field.glsl, probe_blend_value).
ProbeVec3 probe_blend_value(const ProbeField& f, uint32_t probe, ProbeVec3 n) {
  if (f.basis == kProbeBasisSh) return sh_irradiance(f, probe, n);
  float s = 0.0f, t = 0.0f, encoded[4];
  atlas_uv(f, probe, n, f.irradiance_texels, f.irradiance_width, f.irradiance_height, &s, &t);
  bilinear<4>(f.irradiance, f.irradiance_width, f.irradiance_height, s, t, encoded);
  // 2021 paper, fig. 3: decode to gamma 2 for the blend, square after.
  const float exponent = f.irradiance_gamma * 0.5f;
  return {std::pow(std::max(encoded[0], 0.0f), exponent),
          std::pow(std::max(encoded[1], 0.0f), exponent),
          std::pow(std::max(encoded[2], 0.0f), exponent)};
}

// Chebyshev visibility of `biased` from octahedral probe p (field.glsl, chebyshev_visibility).
float chebyshev_visibility(const ProbeField& f, uint32_t probe, ProbeVec3 probe_position,
                           ProbeVec3 biased, ProbeVec3 n) {
  const ProbeVec3 probe_to_point = biased - probe_position;
  const float r = std::sqrt(dot(probe_to_point, probe_to_point));
  float s = 0.0f, t = 0.0f, moments[2];
  atlas_uv(f, probe, safe_normalize(probe_to_point, n), f.distance_texels, f.distance_width,
           f.distance_height, &s, &t);
  bilinear<2>(f.distance, f.distance_width, f.distance_height, s, t, moments);
  if (r <= moments[0]) return 1.0f;
  const float variance = std::fabs(moments[1] - moments[0] * moments[0]);
  const float d = r - moments[0];
  const float chebyshev = variance / std::max(variance + d * d, 1e-30f);
  return chebyshev * chebyshev * chebyshev;
}

// The octahedral field's atlases, or "" when they fit the grid.
const char* atlas_problem(const ProbeField& f, size_t probes) {
  if (f.tiles_per_row == 0) return "tiles_per_row is 0";
  const size_t rows = (probes + f.tiles_per_row - 1) / f.tiles_per_row;
  const auto fits = [&](uint32_t texels, uint32_t width, uint32_t height) {
    const size_t tile = texels + 2u * f.border_texels;
    return texels > 0 && width >= f.tiles_per_row * tile && height >= rows * tile;
  };
  if (!fits(f.irradiance_texels, f.irradiance_width, f.irradiance_height)) {
    return "irradiance_width/height do not hold every probe's tile";
  }
  if (!fits(f.distance_texels, f.distance_width, f.distance_height)) {
    return "distance_width/height do not hold every probe's tile";
  }
  if (f.irradiance.size() != size_t(f.irradiance_width) * f.irradiance_height * 4) {
    return "irradiance: expected width x height x 4 floats";
  }
  if (f.distance.size() != size_t(f.distance_width) * f.distance_height * 2) {
    return "distance: expected width x height x 2 floats";
  }
  return "";
}

}  // namespace

const char* probe_field_problem(const ProbeField& f) {
  const size_t probes = size_t(std::max(f.counts[0], 0)) * size_t(std::max(f.counts[1], 0)) *
                        size_t(std::max(f.counts[2], 0));
  if (probes == 0) return "counts: every axis needs at least one probe";
  if (!(f.spacing.x > 0.0f && f.spacing.y > 0.0f && f.spacing.z > 0.0f)) {
    return "spacing must be positive on every axis";
  }
  if (f.probe_states.size() != probes * 4) return "probe_states: expected 4 floats per probe";
  if (f.basis == kProbeBasisSh) {
    return f.sh.size() == probes * 27 ? "" : "sh: expected 27 floats per probe";
  }
  if (f.basis != kProbeBasisOctahedral) return "basis must be 0 (octahedral) or 1 (sh)";
  return atlas_problem(f, probes);
}

ProbeVec3 probe_field_irradiance(const ProbeField& f, ProbeVec3 p, ProbeVec3 n,
                                 ProbeVec3 to_viewer) {
  const float min_spacing = std::min(f.spacing.x, std::min(f.spacing.y, f.spacing.z));
  // 2021 paper, eq. 2: one bias along the normal and the view direction.
  const ProbeVec3 biased =
      p + ((n * 0.2f + to_viewer * 0.8f) * (0.75f * min_spacing)) * f.self_shadow_bias;
  const float grid[3] = {(biased.x - f.origin.x) / f.spacing.x,
                         (biased.y - f.origin.y) / f.spacing.y,
                         (biased.z - f.origin.z) / f.spacing.z};
  int base[3];
  float alpha[3];
  for (int axis = 0; axis < 3; ++axis) {
    const int last = f.counts[axis] - 1;
    base[axis] = std::clamp(int(std::floor(grid[axis])), 0, std::max(last - 1, 0));
    alpha[axis] = std::clamp(grid[axis] - float(base[axis]), 0.0f, 1.0f);
  }

  ProbeVec3 sum;
  float weight_sum = 0.0f;
  for (uint32_t i = 0; i < 8; ++i) {
    const int offset[3] = {int(i & 1u), int((i >> 1) & 1u), int((i >> 2) & 1u)};
    int coord[3];
    for (int axis = 0; axis < 3; ++axis) {
      coord[axis] = std::min(base[axis] + offset[axis], f.counts[axis] - 1);
    }
    const uint32_t probe = uint32_t(coord[0] + f.counts[0] * (coord[1] + f.counts[1] * coord[2]));
    const float* state = &f.probe_states[size_t(probe) * 4];
    if (state[3] == float(kProbeOff)) continue;
    const ProbeVec3 probe_position = {f.origin.x + f.spacing.x * float(coord[0]) + state[0],
                                      f.origin.y + f.spacing.y * float(coord[1]) + state[1],
                                      f.origin.z + f.spacing.z * float(coord[2]) + state[2]};

    float trilinear = 1.0f;
    for (int axis = 0; axis < 3; ++axis) {
      trilinear *= offset[axis] ? alpha[axis] : 1.0f - alpha[axis];
    }
    // Wrap shading: probes behind the surface count less (thesis eq. 4.4 with a = 1).
    const ProbeVec3 to_probe = safe_normalize(probe_position - p, n);
    const float wrap = (dot(to_probe, n) + 1.0f) * 0.5f;
    float weight = wrap * wrap + 0.2f;

    // Octahedral probes know what they see (their distance moments); SH probes do not.
    if (f.basis == kProbeBasisOctahedral) {
      weight *= chebyshev_visibility(f, probe, probe_position, biased, n);
    }
    // Crush tiny weights: light leaking through thin walls shows at low weights.
    weight = std::max(weight, 1e-6f);
    const float c = f.weight_crush_threshold;
    if (weight < c) weight *= weight * weight / (c * c);
    weight *= std::max(trilinear, 0.0f);

    sum = sum + probe_blend_value(f, probe, n) * weight;
    weight_sum += weight;
  }
  if (!(weight_sum > 0.0f)) return {};
  ProbeVec3 blended = {sum.x / weight_sum, sum.y / weight_sum, sum.z / weight_sum};
  if (f.basis == kProbeBasisOctahedral) {
    blended = {blended.x * blended.x, blended.y * blended.y, blended.z * blended.z};
  }
  const auto sanitize = [](float v) { return std::isfinite(v) ? std::max(v, 0.0f) : 0.0f; };
  return {sanitize(blended.x), sanitize(blended.y), sanitize(blended.z)};
}

}  // namespace ddgi
