// Parameters of one DDGI irradiance field: the probe grid and how it is traced, blended and
// sampled. One struct; one table declaring each parameter's name, range and short doc once
// (field_param_table(), in field_params.cpp; see gi/param_table.h), from which validate(), the
// by-name text form (CLI --field, config files, the RPC API), the help text and the range tests
// are derived. References: Majercik et al. 2019/2021 ("the 2021 paper") and Hvezda 2022
// ("the thesis"), in ../shared/papers/.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"
#include "gi/param_table.h"
#include "gi/probe_grid.h"
#include "gpu_scene/frame_types.h"
#include "scene/scene.h"
#include "shared/field_data.h"

namespace ddgi {

// What each probe stores of the light it sees (docs/sh-probes.md).
enum class ProbeBasis : uint32_t {
  // Octahedral irradiance and distance maps: visibility-aware, 4.2 KB per probe at the default
  // texel counts (DDGI, the 2019/2021 papers).
  kOctahedral = gpu::kFieldBasisOctahedral,
  // L2 spherical harmonics of radiance, nine RGB coefficients (108 B on the GPU, less on the
  // wire), no visibility (DDISH-GI, Ikkala et al. 2022): cheap to stream to clients.
  kSh = gpu::kFieldBasisSh,
};

struct IrradianceFieldParams {
  // --- Grid ---------------------------------------------------------------------------------
  // World position of probe (0,0,0). Finite.
  glm::vec3 origin{0.0f};
  // Distance between neighbouring probes per axis. Finite, > 0. Sets the scale of every
  // distance-based quantity (self-shadow bias, visibility range).
  glm::vec3 spacing{1.0f};
  // Probes per axis, each in [1, 512], total <= 4,194,304. Any count, not only powers of two.
  glm::ivec3 counts{4, 4, 4};
  // Follow the camera (a tracking window, 2021 paper sec. 7.2; docs/cascades.md): when the
  // camera is a cell or more from the grid's centre on an axis, the grid scrolls by whole
  // cells so the camera is within a cell of the centre again; only the planes that enter are
  // traced anew. Off by default: a grid fitted to the scene covers it all.
  bool track_camera = false;
  // Cascades (thesis sec. 6.2; docs/cascades.md): this many volumes of `counts` probes around
  // the same centre, volume i spaced spacing x cascade_spacing_ratio^i (finest first), sampled
  // with blend weights across them; with track_camera each scrolls on its own cell. [1, 8]. 1:
  // one grid, as a fitted field is.
  uint32_t cascades = 1;
  // Each cascade's spacing over the previous one's, [1, 16]. 2: the thesis's pyramid (each
  // level covers 8x the volume at the same probe count).
  float cascade_spacing_ratio = 2.0f;
  // Static volumes (docs/cascades.md): grids of their own beside the field's grid or cascades,
  // placed by the scene (sidecar `probe_volumes`) or the caller, e.g. a fine grid in one room of
  // a street. They never track the camera. All volumes are sampled finest first (by each one's
  // largest spacing). At most 8 volumes in all (kMaxFieldVolumes), cascades included. None by
  // default.
  std::vector<GridPlacement> static_volumes;

  // --- Tracing ------------------------------------------------------------------------------
  // Rays per probe per update that are shaded and blended, in [1, 1024]. 128 keeps noise low at
  // the default hysteresis (the thesis finds 64 enough for stable sampling; 2021 uses 256).
  uint32_t rays_per_probe = 128;
  // Extra rays per probe in a fixed (never rotated) pattern, in [0, 256]. Traced for hit
  // distances only, never shaded or blended: relocation and classification need directions that
  // do not change between updates (2021 paper, RTXGI).
  uint32_t fixed_rays = 32;
  // Rays longer than this are misses and see the environment. (0, 1e30]. Infinite by default:
  // the field should see the whole scene.
  float max_ray_distance = 1e30f;

  // --- Probe basis --------------------------------------------------------------------------
  // Octahedral maps (the default: they carry visibility, so light does not leak through walls)
  // or SH coefficients (docs/sh-probes.md). Changing it starts the field over.
  ProbeBasis basis = ProbeBasis::kOctahedral;
  // SH fields: width w of the Hanning window h_l = (1 + cos(pi l / w)) / 2 that damps band l
  // against ringing, in [0, 64]; 0: no window. 0 by default: the cosine lobe already damps band
  // 2 to a quarter and negative irradiance is clamped; docs/sh-probes.md measures both.
  float sh_window = 0.0f;

  // --- Atlases (octahedral basis) ---------------------------------------------------------
  // Interior side of each probe's octahedral irradiance map, in [4, 32]. 8: irradiance is
  // smooth (2021 paper).
  uint32_t irradiance_texels = 8;
  // Interior side of each probe's distance map, in [4, 64]. 16: visibility needs more detail
  // than irradiance (2021 paper).
  uint32_t distance_texels = 16;

  // --- Blending -----------------------------------------------------------------------------
  // Weight of the previous value per update, in [0, 0.999]. 0.97: the 2021 paper's default
  // trade of stability against lag.
  float hysteresis = 0.97f;
  // Same for the distance moments, in [0, 0.999]; the 2021 paper keeps visibility steadier.
  float distance_hysteresis = 0.97f;
  // A texel whose value changes by more than this fraction of its magnitude (in the encoded
  // space) lowers its hysteresis by 0.15, in [0, 1]. 0.25 (2021 paper, sec. 4.3, taken
  // relative to the texel's magnitude so it behaves the same at every light intensity).
  float change_threshold = 0.25f;
  // Beyond this relative change the old value is dropped (hysteresis 0), in [0, 1]. 0.8: the
  // distribution changed completely (2021 paper).
  float new_distribution_threshold = 0.8f;
  // Perceptual encoding exponent of stored irradiance, in [1, 10]. 5 (2021 paper): faster
  // light-to-dark convergence and fewer firefly flickers. 1 stores linear irradiance.
  float irradiance_gamma = 5.0f;
  // Power-cosine exponent of the distance blend, in [1, 100]. 50: sharp visibility moments
  // (2019 paper, RTXGI; the thesis's k_s).
  float distance_exponent = 50.0f;
  // Back-face hits shorten their distance to this fraction, in [0, 1]. 0.2: "shorten by 80%"
  // (2021 paper, sec. 4.1), so probes see back faces as shadowed without a zero distance.
  float backface_distance_scale = 0.2f;

  // --- Sampling -----------------------------------------------------------------------------
  // The 2021 paper's single self-shadow bias B (eq. 2), in [0, 2]. 0.3: its default.
  float self_shadow_bias = 0.3f;
  // Light arriving at probe-ray hits: 0 reads the previous field there (DDGI: one more bounce
  // per update, infinitely many over time); N > 0 traces a path of up to N further vertices
  // with next-event estimation at each and Russian roulette after the fourth (DDISH-GI's
  // update: no lag in the first N bounces, at N traced rays more per probe ray), reading the
  // previous field where a path reaches its N-th vertex (the later bounces' light, which a cut
  // path would lose), in [0, 64] (the roulette ends most paths long before). docs/sh-probes.md
  // measures both; 0 is kept as the default.
  uint32_t probe_bounces = 0;
  // Multiplies irradiance fed back into probe-ray shading, in [0, 1]. 1: energy conserving
  // (the furnace test converges to Le / (1 - rho)); lower it to damp runaway feedback.
  float energy_conservation = 1.0f;
  // Weights below this are crushed (w^3 / c^2), in [0, 1]. 0.2 (RTXGI, thesis eq. 4.10).
  float weight_crush_threshold = 0.2f;

  // --- Probe management (docs/probe-management.md) -------------------------------------------
  // Relocation passes at initialisation and when geometry moves, in [0, 16]. 5: enough for
  // almost every probe to settle, few enough that no probe oscillates through tangent faces
  // (2021 paper, sec. 5). 0 leaves probes on their grid points.
  uint32_t relocation_iterations = 5;
  // Classify probes into Off / Sleeping / Vigilant / Awake and trace only active ones. Off
  // probes (inside geometry) are also left out of shading (thesis Fig. 6.2).
  bool classification = true;
  // Relocation keeps each probe within this fraction of the spacing of its grid point, per
  // axis, in [0, 0.49]. 0.45: probes stay in their cell, so cage lookups stay valid.
  float probe_offset_limit = 0.45f;
  // Relocation moves probes at least this far from front faces, as a fraction of the smallest
  // spacing, in [0, 0.5]. 0.4: probes hugging a surface make the Chebyshev test fragile; on the
  // two-room scene 0.1 / 0.25 / 0.4 leave 0.28 / 0.22 / 0.17% of the lit room's light in the
  // dark room (docs/probe-management.md).
  float min_frontface_distance = 0.4f;
  // A probe with more back-face hits than this fraction of its fixed rays is inside
  // geometry, in (0, 1]. 0.25: the 2021 paper's threshold.
  float backface_threshold = 0.25f;
  // Probe rays one update may trace (rays_per_probe per probe: updates do not trace the fixed
  // rays, probe management does); 0: no cap. When the active probes need more, each update
  // traces a round-robin window of them. Must be 0 or at least rays_per_probe. Shadow rays are
  // not counted.
  uint64_t max_rays_per_update = 0;

  // --- Adaptive rays (docs/adaptive-rays.md) -------------------------------------------------
  // A probe is hot while its irradiance still drifts: the difference between an update's
  // estimate and the probe's history (mean luminance and mean direction over its texels,
  // relative to their size), averaged over its last traced updates, above this fraction. Hot
  // probes, and every probe for hot_updates updates after the scene changed, are traced every
  // update; settled ones only in the maintenance slice. 0: every active probe every update
  // (fixed rays); 0.01 in the tests. In [0, 1]. The octahedral basis and the fused update path
  // only. docs/adaptive-rays.md.
  float settle_threshold = 0.0f;
  // Updates a probe stays hot after its drift last exceeded settle_threshold, and updates that
  // trace every probe after the scene changed, in [1, 255]. 8: on the two-room test (hysteresis
  // 0.8, threshold 0.01) the field catches up to within 0.001 of fixed rays' error for 46% of
  // their probe updates over the 48 after a light move (16: 2x the error left at 0.02, 54%).
  uint32_t hot_updates = 8;
  // Fraction of the active probes each adaptive update traces whatever their heat, round robin,
  // in [0.001, 1]: the maintenance rate that finds changes the scene did not announce (light
  // carried in by other probes). 0.125: every probe at least every 8 updates.
  float maintenance_rate = 0.125f;

  // --- Emitters ---------------------------------------------------------------------------------
  // Light from emissive surfaces, sampled directly instead of carried by the field: each pixel
  // and each probe-ray hit takes this many samples on the emitters (a triangle picked by area x
  // luminance, a direction in the solid angle it subtends, one shadow ray each), and probe rays
  // no longer carry the emission they see (it would count twice). 0: off, emitter light reaches
  // surfaces through the field (probe rays hit the emitters, the 2021 paper's way). [0, 64]. 0
  // here; a scene whose emissive surfaces put out kEmitterShareToSample of its light or more
  // (gi/light_power.h) gets kSceneEmitterSamples from default_field_params: carried by the
  // field, a small bright emitter loses light (few probe rays hit it, and the perceptual
  // encoding's temporal blend is a power mean that undercounts rare bright hits: -37% in
  // DefaultEnergyTest's room, -16 to -19% on cornell_kajiya and veach_ajar,
  // docs/results/default-energy.md) and a probe grid cannot hold its steep near field. Sampled,
  // it is noisier per pixel but unbiased.
  uint32_t emitter_samples = 0;

  // --- Paths per pixel (docs/service.md, "Paths per pixel") ----------------------------------
  // The frame's indirect light per pixel, in [0, 64]: 0 reads the field at the pixel (DDGI);
  // N > 0 traces N cosine-weighted paths from the pixel instead, each of at most
  // pixel_path_vertices vertices with probe_bounces' rule (next-event estimation at every
  // vertex, Russian roulette after the fourth), reading the field where it ends. Light a probe
  // grid cannot hold, the near field of cavities and gaps narrower than the probe spacing
  // (cornell_nvpro's albedo-1 slot around its lamp, docs/results/default-energy.md), then
  // reaches the pixel, at the noise of N paths per pixel and N x vertices rays. 0: the default.
  uint32_t pixel_paths = 0;
  // Vertices of each path per pixel, in [1, 64]. 32: light leaves an albedo-1 cavity only after
  // tens of bounces (cornell_nvpro keeps 0.61 / 0.76 / 0.96 of its light with 2 / 8 / 32);
  // elsewhere the roulette ends most paths long before.
  uint32_t pixel_path_vertices = 32;

  // --- Direct light at probe-ray hits (docs/shadow-field.md, "Probe rays") -------------------
  // How punctual lights light the probe-ray hits: a direct mode of its own, or none (the
  // default) to follow the mode of the frame or update that runs the field. The field is a
  // blurred, lagging estimate anyway, so its direct light can be cheaper than the frame's:
  // e.g. frames with exact shadow rays, probe rays reading the shadow field. The shadow-field
  // and AO modes need a shadow field; without one they trace shadow rays.
  std::optional<DirectMode> probe_direct;

  // --- Determinism ----------------------------------------------------------------------------
  // Seed of the per-update random ray rotation: the same seed gives the same field.
  uint32_t seed = 1;

  bool operator==(const IrradianceFieldParams&) const = default;
};

// Every parameter by name: its range, its text form and its help (field_params.cpp).
const ParamTable<IrradianceFieldParams>& field_param_table();
extern template class ParamTable<IrradianceFieldParams>;

// The table's ranges (errors name the field and its allowed range), then the rules across
// parameters.
Status validate(const IrradianceFieldParams& params);

// A grid fitted to `bounds`: about `target_probes` probes (512: 8x8x8 for a cube, enough for a
// room, cheap enough for a CPU device; pass more for large scenes), cell-centred (probes sit half a
// spacing inside the bounds, so a room's probes are not on its walls), at least 1 per axis.
IrradianceFieldParams fit_grid_to_bounds(const Bounds& bounds, uint32_t target_probes = 512,
                                         IrradianceFieldParams base = {});

// Emitter samples per pixel and probe-ray hit an emitter-lit scene gets by default
// (IrradianceFieldParams::emitter_samples says why). 2: the frame's mean within 1% of 8
// samples' on cornell_kajiya at half their frame cost (docs/results/default-energy.md).
inline constexpr uint32_t kSceneEmitterSamples = 2;

// What a user gets without setting anything: the grid the scene asks for (sidecar
// `probe_grid`), else one fitted to its bounds (objects on a far-reaching ground plane: to them
// and the ground around them), the sidecar's static volumes, and emitter
// sampling where emissive surfaces carry a share of the scene's light (emitters_worth_sampling).
IrradianceFieldParams default_field_params(const Scene& scene);

// Probes of the whole field: every volume's.
uint64_t probe_count(const IrradianceFieldParams& params);

// One volume of a field (docs/cascades.md): its grid and where its probes start among the
// field's slots.
struct FieldVolume {
  glm::vec3 origin{0.0f};
  glm::vec3 spacing{1.0f};
  glm::ivec3 counts{1};
  uint32_t first_probe = 0;
  // What placed it: cascade `cascade` of the field's grid (0: the grid itself), or, when set,
  // params.static_volumes[*static_volume].
  uint32_t cascade = 0;
  std::optional<uint32_t> static_volume;
  // Whether it follows the camera when the field tracks it (the cascades do, static volumes not).
  bool tracks(const IrradianceFieldParams& params) const {
    return params.track_camera && !static_volume;
  }
};
// The volumes of `params` as placed at creation, finest first (blend order, and the order of
// their probes among the field's slots): the cascades around the grid's centre and the static
// volumes, each kept where the largest of its spacings puts it (cascades first on ties).
std::vector<FieldVolume> field_volumes(const IrradianceFieldParams& params);

// A scrolling grid's addressing (FieldConstants::scroll, shaders/common/field.glsl): the slot
// (index into the probe arrays and atlases) of the probe at grid coordinate `coord`, and the
// grid coordinate of the probe in `slot`. `scroll`: each axis in [0, counts).
uint32_t probe_slot(glm::ivec3 counts, glm::ivec3 scroll, glm::ivec3 coord);
glm::ivec3 probe_coord(glm::ivec3 counts, glm::ivec3 scroll, uint32_t slot);

// The whole cells a tracking grid scrolls so that `camera` is within a cell of its centre on
// every axis; zero while it is (moves of less than a cell never scroll, so a camera moving
// to and fro across a cell border does not make the grid flicker between two places).
glm::ivec3 tracking_scroll(const FieldVolume& volume, glm::vec3 camera);

// The mode a shadow field is updated in when it serves a frame in `frame_mode` and the probe
// rays of an irradiance field with `field` (null: no field, or not updated): the frame's when
// the frame reads the shadow field, else the probe rays' (probe_direct). Nothing reads the
// shadow field unless uses_shadow_field() of the result.
DirectMode shadow_field_mode(DirectMode frame_mode, const IrradianceFieldParams* field);

// Hit distances in a field's moments atlas (irradiance and shadow fields) are clamped to this:
// 1.5 x the cell diagonal, the reach of a probe's visibility, and at most 1e17 so that weighted
// sums of squared distances over 1024 rays stay inside fp32 (1024 x 1e34 < 3.4e38) however
// huge the spacing (computed in double: the diagonal alone can overflow a float).
float visibility_range(glm::vec3 spacing);

// Where each probe's maps live in the two atlases (see shaders/shared/field_data.h).
struct AtlasLayout {
  uint32_t tiles_per_row = 1;
  uint32_t rows = 1;
  glm::uvec2 irradiance_size{0};  // texels, borders included
  glm::uvec2 distance_size{0};
};
AtlasLayout atlas_layout(const IrradianceFieldParams& params);
// The factors of SH bands 0, 1 and 2 in M = E / pi: A_l / pi times the ringing window (band 0:
// 1; bands 1 and 2 are FieldConstants::sh_band1/2, shaders/common/sh.glsl), as the dumps and
// the probe stream give them to clients.
std::array<float, 3> sh_band_scales(const IrradianceFieldParams& params);
// Bytes of one probe's larger map tile, borders included (RGBA32F irradiance, RG32F distance).
uint64_t largest_map_tile_bytes(const IrradianceFieldParams& params);
// Probe-ray hit records a field holds for the fused update's hit-light pass: one per ray where it
// reads the field at probe-ray hits, else (the trace follows paths from them, probe_bounces > 0)
// one, so that the binding stays valid.
uint64_t probe_ray_hit_records(const IrradianceFieldParams& params);
// Bytes of GPU memory the field's atlases and ray buffers need (checked against the budget
// before anything is allocated).
uint64_t field_gpu_bytes(const IrradianceFieldParams& params);

}  // namespace ddgi
