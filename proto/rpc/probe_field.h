// The irradiance field as a client receives it (the probe grid; its irradiance and distance
// atlases, or for SH fields each probe's nine SH coefficients; each probe's relocation offset
// and state) and its irradiance query, written as the server's shader writes it
// (shaders/common/field.glsl, sample_irradiance): the same cage of 8 probes, bias, wrap
// shading, Chebyshev visibility (octahedral probes), weight crushing, bilinear atlas reads
// (clamped to the edge) and gamma decoding, or the SH irradiance (shaders/common/sh.glsl). For
// clients that shade from downloaded probes (CI jobs asking for irradiance without a round trip, a
// local renderer); web/probes.js is the same function for browsers. Plain C++ with no dependency,
// so it can be copied into any client.
#pragma once

#include <cstdint>
#include <vector>

namespace ddgi {

struct ProbeVec3 {
  float x = 0.0f, y = 0.0f, z = 0.0f;
};

// ProbeField::basis (shaders/shared/field_data.h, kFieldBasis*).
inline constexpr uint32_t kProbeBasisOctahedral = 0;
inline constexpr uint32_t kProbeBasisSh = 1;

struct ProbeField {
  uint32_t basis = kProbeBasisOctahedral;
  int counts[3] = {0, 0, 0};       // probes per axis
  ProbeVec3 origin;                // probe (0,0,0) before relocation
  ProbeVec3 spacing;               // between neighbours, per axis
  uint32_t irradiance_texels = 0;  // interior side of a probe's irradiance map
  uint32_t distance_texels = 0;    // interior side of a probe's distance map
  uint32_t border_texels = 1;      // on each side of each tile
  uint32_t tiles_per_row = 0;
  float irradiance_gamma = 5.0f;        // stored as value^(1/gamma)
  float self_shadow_bias = 0.3f;        // field parameter self_shadow_bias
  float weight_crush_threshold = 0.2f;  // field parameter weight_crush_threshold
  // RGBA, row-major, row 0 first (DumpAtlas RAW_F32).
  uint32_t irradiance_width = 0, irradiance_height = 0;
  std::vector<float> irradiance;
  // mean, mean of squares.
  uint32_t distance_width = 0, distance_height = 0;
  std::vector<float> distance;
  // Per probe (x fastest, then y, then z): relocation offset x, y, z and state (3: off).
  std::vector<float> probe_states;
  // SH fields only (the atlases are then empty): 9 RGB coefficients per probe (27 floats, in
  // probe order) and the factor of bands 0, 1, 2 in M (DumpAtlas ATLAS_KIND_SH).
  std::vector<float> sh;
  float sh_band_scales[3] = {1.0f, 2.0f / 3.0f, 0.25f};
};

// Empty when the field is consistent (sizes of every array agree with the grid); otherwise
// what is wrong, naming the member.
const char* probe_field_problem(const ProbeField& field);

// Cosine-weighted mean radiance M = E / pi arriving at `position` around unit `normal`, as the
// server's QueryIrradiance returns it. `to_viewer`: unit direction towards whoever looks (the
// self-shadow bias leans that way; the normal when no one does).
ProbeVec3 probe_field_irradiance(const ProbeField& field, ProbeVec3 position, ProbeVec3 normal,
                                 ProbeVec3 to_viewer);

}  // namespace ddgi
