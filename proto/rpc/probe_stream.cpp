#include "rpc/probe_stream.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ddgi {
namespace {

constexpr uint32_t kShValues = 27;

bool bit(const std::string& mask, size_t p) {
  return p / 8 < mask.size() && (uint8_t(mask[p / 8]) >> (p % 8) & 1u) != 0;
}

// Reads `count` fp16 values at `*at` of `bytes`; false past the end.
bool take_halves(const std::string& bytes, size_t* at, size_t count, float* out) {
  if (count > (bytes.size() - std::min(*at, bytes.size())) / 2) return false;
  for (size_t i = 0; i < count; ++i) {
    const uint16_t h = uint16_t(uint8_t(bytes[*at + 2 * i])) |
                       uint16_t(uint16_t(uint8_t(bytes[*at + 2 * i + 1])) << 8);
    out[i] = half_to_float(h);
  }
  *at += count * 2;
  return true;
}

// A new field of `grid`'s shape, every value zero.
Result<ProbeField> field_of_grid(const v1::ProbeGrid& g) {
  ProbeField f;
  f.counts[0] = g.counts_x();
  f.counts[1] = g.counts_y();
  f.counts[2] = g.counts_z();
  f.origin = {g.origin().x(), g.origin().y(), g.origin().z()};
  f.spacing = {g.spacing().x(), g.spacing().y(), g.spacing().z()};
  f.self_shadow_bias = g.self_shadow_bias();
  f.weight_crush_threshold = g.weight_crush_threshold();
  const int64_t probes = int64_t(f.counts[0]) * f.counts[1] * f.counts[2];
  if (f.counts[0] <= 0 || f.counts[1] <= 0 || f.counts[2] <= 0 || probes > (1 << 24)) {
    return invalid_argument("probe grid: counts must be positive, at most 2^24 probes");
  }
  f.probe_states.assign(size_t(probes) * kProbeStateValues, 0.0f);
  if (g.basis() == "sh") {
    f.basis = kProbeBasisSh;
    for (int band = 0; band < 3 && band < g.sh_band_scales_size(); ++band) {
      f.sh_band_scales[band] = g.sh_band_scales(band);
    }
    f.sh.assign(size_t(probes) * kShValues, 0.0f);
    return f;
  }
  if (g.basis() != "octahedral") return invalid_argument("probe grid: unknown basis " + g.basis());
  if (g.irradiance_texels() == 0 || g.irradiance_texels() > 64 || g.distance_texels() == 0 ||
      g.distance_texels() > 64 || g.border_texels() > 8 || g.tiles_per_row() == 0 ||
      g.tiles_per_row() > (1u << 16)) {
    return invalid_argument("probe grid: texels, border or tiles_per_row out of range");
  }
  f.irradiance_texels = g.irradiance_texels();
  f.distance_texels = g.distance_texels();
  f.border_texels = g.border_texels();
  f.tiles_per_row = g.tiles_per_row();
  f.irradiance_gamma = g.irradiance_gamma();
  const uint32_t rows = uint32_t((probes + f.tiles_per_row - 1) / f.tiles_per_row);
  const uint32_t it = f.irradiance_texels + 2 * f.border_texels;
  const uint32_t dt = f.distance_texels + 2 * f.border_texels;
  f.irradiance_width = f.tiles_per_row * it;
  f.irradiance_height = rows * it;
  f.distance_width = f.tiles_per_row * dt;
  f.distance_height = rows * dt;
  f.irradiance.assign(size_t(f.irradiance_width) * f.irradiance_height * 4, 0.0f);
  f.distance.assign(size_t(f.distance_width) * f.distance_height * 2, 0.0f);
  return f;
}

// Puts probe p's values (probe_value_count floats) where the field keeps them.
void store_probe(ProbeField& f, size_t p, const float* v) {
  if (f.basis == kProbeBasisSh) {
    std::copy(v, v + kShValues, f.sh.begin() + std::ptrdiff_t(p * kShValues));
    return;
  }
  auto place = [&](std::vector<float>& atlas, uint32_t width, uint32_t texels, uint32_t channels,
                   uint32_t stored, const float* from) {
    const uint32_t tile = texels + 2 * f.border_texels;
    const size_t x0 = (p % f.tiles_per_row) * tile, y0 = (p / f.tiles_per_row) * tile;
    for (uint32_t y = 0; y < tile; ++y) {
      for (uint32_t x = 0; x < tile; ++x) {
        float* texel = &atlas[((y0 + y) * width + x0 + x) * channels];
        for (uint32_t c = 0; c < stored; ++c) texel[c] = *from++;
      }
    }
    return from;
  };
  const float* rest = place(f.irradiance, f.irradiance_width, f.irradiance_texels, 4, 3, v);
  // The stream sends (mean, variance); the field keeps (mean, mean of squares).
  std::vector<float> moments(rest, rest + 2 * size_t(f.distance_texels + 2 * f.border_texels) *
                                              (f.distance_texels + 2 * f.border_texels));
  for (size_t i = 0; i < moments.size(); i += 2) moments[i + 1] += moments[i] * moments[i];
  place(f.distance, f.distance_width, f.distance_texels, 2, 2, moments.data());
}

}  // namespace

uint16_t float_to_half(float value) {
  if (std::isnan(value)) return 0;
  value = std::clamp(value, -65504.0f, 65504.0f);
  uint32_t bits = 0;
  std::memcpy(&bits, &value, 4);
  const uint32_t sign = (bits >> 16) & 0x8000u;
  bits &= 0x7fffffffu;
  if (bits < 0x38800000u) {
    // Below the smallest normal half (2^-14): a subnormal, rounded to nearest even by adding
    // 0.5 in float arithmetic (exact for these magnitudes).
    float magnitude = 0.0f;
    std::memcpy(&magnitude, &bits, 4);
    return uint16_t(sign | uint32_t(std::nearbyint(magnitude * 16777216.0f)));  // x 2^24
  }
  // Rebias the exponent (127 -> 15) and round the 23-bit mantissa to 10 bits, nearest even.
  const uint32_t rounded = bits + 0x0fffu + ((bits >> 13) & 1u);
  return uint16_t(sign | ((rounded - 0x38000000u) >> 13));
}

float half_to_float(uint16_t half) {
  const uint32_t sign = uint32_t(half & 0x8000u) << 16;
  const uint32_t exponent = (half >> 10) & 0x1fu;
  const uint32_t mantissa = half & 0x3ffu;
  float magnitude;
  if (exponent == 0) {
    magnitude = float(mantissa) / 16777216.0f;  // subnormal: mantissa x 2^-24
  } else if (exponent == 31) {
    magnitude = mantissa ? 0.0f : 65504.0f;  // never written: infinities and NaN read as limits
  } else {
    const uint32_t bits = ((exponent + 112u) << 23) | (mantissa << 13);
    std::memcpy(&magnitude, &bits, 4);
  }
  uint32_t bits = 0;
  std::memcpy(&bits, &magnitude, 4);
  bits |= sign;
  float out = 0.0f;
  std::memcpy(&out, &bits, 4);
  return out;
}

uint32_t probe_value_count(const v1::ProbeGrid& g) {
  if (g.basis() == "sh") return kShValues;
  const uint32_t it = g.irradiance_texels() + 2 * g.border_texels();
  const uint32_t dt = g.distance_texels() + 2 * g.border_texels();
  return it * it * 3 + dt * dt * 2;
}

Status apply_probe_update(const v1::ProbeUpdate& update, StreamedField* streamed) {
  ProbeField& f = streamed->field;
  if (update.full()) {
    DDGI_ASSIGN_OR_RETURN(f, field_of_grid(update.grid()));
    streamed->stride = probe_value_count(update.grid());
  } else if (f.probe_states.empty()) {
    return invalid_argument("a probe update that is not full came before any full one");
  }
  const size_t probes = f.probe_states.size() / kProbeStateValues;
  std::vector<float> values(streamed->stride);
  size_t at = 0;
  for (size_t p = 0; p < probes; ++p) {
    if (!update.full() && !bit(update.changed(), p)) continue;
    if (!take_halves(update.values(), &at, values.size(), values.data())) {
      return invalid_argument("probe update: values end before probe " + std::to_string(p));
    }
    store_probe(f, p, values.data());
  }
  if (at != update.values().size()) return invalid_argument("probe update: values left over");
  at = 0;
  for (size_t p = 0; p < probes; ++p) {
    if (!update.full() && !bit(update.state_changed(), p)) continue;
    if (!take_halves(update.states(), &at, kProbeStateValues, &f.probe_states[p * 4])) {
      return invalid_argument("probe update: states end before probe " + std::to_string(p));
    }
  }
  if (at != update.states().size()) return invalid_argument("probe update: states left over");
  streamed->field_updates = update.field_updates();
  ++streamed->messages;
  streamed->bytes += update.ByteSizeLong();
  return ok_status();
}

}  // namespace ddgi
