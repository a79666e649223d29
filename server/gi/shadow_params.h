// Parameters of one shadow field (docs/shadow-field.md): its own probe grid, how it traces and
// blends light visibility, and how a shading point samples it. One struct; one table declaring
// each parameter's name, range and short doc once (shadow_param_table(), in shadow_params.cpp;
// see gi/param_table.h), from which validate(), the by-name text form (CLI --shadow-field, the
// RPC API), the help text and the range tests are derived. References: Hvezda 2022 ("the
// thesis", ch. 5) and Majercik et al. 2019/2021 for what the shadow field shares with the
// irradiance field (octahedral maps, distance moments, Chebyshev visibility).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "core/result.h"
#include "gi/param_table.h"
#include "scene/scene.h"

namespace ddgi {

// How probes are weighted when a shading point samples the field (thesis sec. 5.2, Fig. 5.3).
enum class ShadowWeighting : uint32_t {
  kCosine = 0,  // max(0, n . to_probe): probes behind the surface count nothing (leaks less)
  kWrap = 1,    // ((n . to_probe + 1) / 2)^2: the irradiance field's wrap shading
};

// What lights past the kept ones get in the shadow-field and AO modes.
enum class ShadowOverflow : uint32_t {
  kTracedShadows = 0,  // one shadow ray per pixel each, as in the shadow-rays mode
  kUnshadowed = 1,     // no shadows at all: cheap, wrong where they would be occluded
};

struct ShadowFieldParams {
  // --- Grid (independent of the irradiance field's) ------------------------------------------
  // World position of probe (0,0,0). Finite.
  glm::vec3 origin{0.0f};
  // Distance between neighbouring probes per axis. Finite, > 0. Biases scale with it.
  glm::vec3 spacing{1.0f};
  // Probes per axis, each in [1, 256], total <= 1,048,576.
  glm::ivec3 counts{4, 4, 4};

  // --- Tracing -------------------------------------------------------------------------------
  // Probe rays per probe per update, in [1, 1024]. 64: the thesis's shadow field (Fig. 7.9);
  // each ray then casts one shadow ray per kept light (and one AO ray in the AO mode).
  uint32_t rays_per_probe = 64;
  // Lights kept in the atlas, in [1, 8] (one RGBA32F channel each, four per atlas group). 4:
  // one group, the most a single RGBA texel holds. The first max_lights lights of the scene (in
  // its order) are kept; the others follow `overflow`.
  uint32_t max_lights = 4;
  // What lights past max_lights get in the shadow-field and AO modes. Traced shadow rays by
  // default: correct, at the per-pixel cost the field exists to avoid, and only for those lights.
  ShadowOverflow overflow = ShadowOverflow::kTracedShadows;
  // Trace primary and shadow rays in one pass, each update shadowing the surfels the previous
  // update found (the thesis's two-frame scheme, Fig. 5.2), instead of two passes of the same
  // update. Off: measured in docs/shadow-field.md (the same rays; the split saves a pass and a
  // barrier but lags geometry changes by one update).
  bool split_update = false;
  // Probe rays longer than this see nothing (visibility 1, AO open). (0, 1e30].
  float max_ray_distance = 1e30f;
  // AO rays from a surfel longer than this count as open sky, (0, 1e30]. 1e30: the thesis's
  // "global" AO (only the sky counts as open); a finite radius gives classic local AO.
  float ao_distance = 1e30f;

  // --- Atlases -------------------------------------------------------------------------------
  // Interior side of every probe's octahedral maps (visibility and moments), in [4, 64]. 16:
  // the thesis's occlusion maps (Fig. 7.9, 7.10).
  uint32_t texels = 16;

  // --- Blending ------------------------------------------------------------------------------
  // Weight of the previous value per update, in [0, 0.999]. 0.9: visibility jumps when a light
  // moves, so it keeps less history than irradiance (0.97); the light-follow test measures the
  // lag (docs/shadow-field.md).
  float hysteresis = 0.9f;
  // Visibility (and AO) texel w blends ray r with weight max(0, w.r)^this, in [1, 1000], and
  // keeps its history's weight (a weighted moving average). 200: half weight 4.8 degrees off
  // the texel's direction, inside a 16^2 texel, so a texel holds what lies in it (measured in
  // docs/shadow-field.md: 0.021 floor error vs 0.026 at 50). 1 is eq. 5.2's plain cosine, which
  // smears a map's visibility over a hemisphere (0.070).
  float visibility_exponent = 200.0f;
  // The same for the distance moments, in [1, 1000] (the thesis's k_s, eq. 4.14).
  float distance_exponent = 50.0f;
  // Back-face hits shorten their distance to this fraction, in [0, 1]: a probe inside geometry
  // sees everything as occluded (2021 paper, sec. 4.1).
  float backface_distance_scale = 0.2f;

  // --- Sampling ------------------------------------------------------------------------------
  ShadowWeighting weighting = ShadowWeighting::kCosine;
  // Shading points move this far along their normal (x the smallest spacing), in [0, 1]. 0.1:
  // enough to pass the Chebyshev test of the surface they lie on (thesis eq. 4.11's k_n).
  float normal_bias = 0.1f;
  // ... and this far towards the viewer (x the smallest spacing), in [0, 1]. 0.05.
  float view_bias = 0.05f;
  // Sampled visibility is raised to this power, in [1, 16] (thesis Fig. 7.10). 1: unchanged;
  // higher powers darken penumbrae, tightening soft shadows towards their occluders.
  float sharpening = 1.0f;
  // Probe weights below this are crushed (w^3 / c^2), in [0, 1]. 0.2 as the irradiance field.
  float weight_crush_threshold = 0.2f;

  // --- Determinism ---------------------------------------------------------------------------
  // Seed of the per-update ray rotation and of the light and AO jitter.
  uint32_t seed = 7;

  bool operator==(const ShadowFieldParams&) const = default;
};

// Every parameter by name: its range, its text form and its help (shadow_params.cpp).
const ParamTable<ShadowFieldParams>& shadow_param_table();
extern template class ParamTable<ShadowFieldParams>;

// The table's ranges (errors name the parameter and its allowed range), then the atlas size.
Status validate(const ShadowFieldParams& params);

// A grid fitted to `bounds` with about `target_cells` cells (512: 8x8x8 for a cube, cheap
// enough for lavapipe): one probe per cell centre plus a layer half a cell outside each face of
// the bounds, so that surfaces on the bounds have probes in front of them.
ShadowFieldParams fit_shadow_grid(const Bounds& bounds, uint32_t target_cells = 512,
                                  ShadowFieldParams base = {});

uint64_t probe_count(const ShadowFieldParams& params);

struct ShadowAtlasLayout {
  uint32_t tiles_per_row = 1;
  uint32_t tile_rows = 1;         // per light group
  uint32_t light_groups = 1;      // ceil(max_lights / 4)
  glm::uvec2 moments_size{0};     // texels, borders included
  glm::uvec2 visibility_size{0};  // every group, stacked vertically
};
ShadowAtlasLayout shadow_atlas_layout(const ShadowFieldParams& params);

// Bytes of GPU memory the field needs (checked against the budget before allocating).
uint64_t shadow_field_gpu_bytes(const ShadowFieldParams& params);

}  // namespace ddgi
