// The irradiance field on the GPU: descriptor set 2 of the field-update kernels and of every
// frame kernel that samples the field.
//
// Irradiance convention: an irradiance texel stores the cosine-weighted mean radiance around
// its direction n, M(n) = sum max(0, n.w) L(w) / sum max(0, n.w), which estimates E(n) / pi.
// A Lambertian surface of albedo rho then reflects rho * M(n). In a closed furnace of uniform
// radiance L, M = L everywhere.
#ifndef DDGI_SHARED_FIELD_DATA_H
#define DDGI_SHARED_FIELD_DATA_H

#include "shared/interop.h"

DDGI_NAMESPACE_BEGIN

// Set 2: what sampling the field needs (frame kernels and field kernels).
DDGI_CONST uint kFieldSet = 2;
DDGI_CONST uint kFieldBindingConstants = 0;   // FieldConstants (one)
DDGI_CONST uint kFieldBindingProbes = 1;      // ProbeState per probe
DDGI_CONST uint kFieldBindingIrradiance = 2;  // sampler2D, RGBA32F, encoded irradiance
DDGI_CONST uint kFieldBindingDistance = 3;    // sampler2D, RG32F, mean distance and its square
DDGI_CONST uint kFieldBindingSh = 4;          // ShProbe per probe (SH fields; one otherwise)

// Set 1 of the field-update kernels: the rays and the atlases as storage images.
DDGI_CONST uint kFieldUpdateSet = 1;
DDGI_CONST uint kFieldUpdateBindingRays = 0;           // ProbeRay per traced ray
DDGI_CONST uint kFieldUpdateBindingIrradianceOut = 1;  // image2D view of the irradiance atlas
DDGI_CONST uint kFieldUpdateBindingDistanceOut = 2;    // image2D view of the distance atlas
DDGI_CONST uint kFieldUpdateBindingProbeList = 3;      // uint probe index per list entry
DDGI_CONST uint kFieldUpdateBindingSurfels = 4;        // ProbeSurfel per ray (split update only)
DDGI_CONST uint kFieldUpdateBindingDrift = 5;          // 16-byte header, ProbeDrift per probe
DDGI_CONST uint kFieldUpdateBindingHits = 6;           // ProbeRayHit per ray (fused update)

// Atlas layout: probe p's tile is (p % tiles_per_row, p / tiles_per_row); a tile is the
// octahedral map plus a one-texel border copied from the opposite edges.
DDGI_CONST uint kAtlasBorder = 1u;
DDGI_CONST uint kMaxAtlasDimension = 16384u;

// ProbeState::flags, bits 0..7: conditions.
DDGI_CONST uint kProbeResetHistory = 1u;  // no valid history: the next blend uses hysteresis 0
// ProbeState::flags, bits 8..15: the probe's state (docs/probe-management.md).
DDGI_CONST uint kProbeStateShift = 8u;
DDGI_CONST uint kProbeStateMask = 0xFFu << 8u;
DDGI_CONST uint kProbeVigilant = 0u;  // shades static geometry: traced every update
DDGI_CONST uint kProbeAwake = 1u;     // woken by a moving object nearby: traced while it is near
DDGI_CONST uint kProbeSleeping = 2u;  // no surface within reach: not traced
DDGI_CONST uint kProbeOff = 3u;       // inside geometry: never traced, never sampled
DDGI_CONST uint kProbeStateCount = 4u;
// ProbeState::flags, bits 16..23: the probe's heat (adaptive rays, docs/adaptive-rays.md):
// lighting updates left in which it is traced whatever the maintenance slice; 0: settled.
DDGI_CONST uint kProbeHeatShift = 16u;
DDGI_CONST uint kProbeHeatMask = 0xFFu << 16u;

// ProbeSurfel::flags
DDGI_CONST uint kRayHit = 1u;
DDGI_CONST uint kRayFrontFace = 2u;

// FieldConstants::basis: what each probe stores (IrradianceFieldParams::basis).
DDGI_CONST uint kFieldBasisOctahedral = 0u;  // octahedral irradiance and distance maps (DDGI)
DDGI_CONST uint kFieldBasisSh = 1u;          // L2 spherical harmonics of radiance (DDISH-GI)

struct ProbeState {
  vec3 offset;  // from the grid position (relocation); zero until relocation runs
  uint flags;
};

// What one traced probe ray brought back: all the blends and probe management read.
// `distance` says what was hit (shaders/common/field_update.glsl encodes and decodes it):
//   +t: a front face at distance t;  -t (sign bit set, also for t = 0): a back face;
//   +infinity: nothing within max_ray_distance.
struct ProbeRay {
  vec3 radiance;  // towards the probe (0 from back faces and from fixed rays, which are not lit)
  float distance;
};

// The fused update's lit front-face hits, from the trace to the hit-light pass
// (field_hit_light.comp), which adds the light arriving there from the previous field: the
// field query runs in a compute pass of its own, not inside the ray-tracing kernel (where its
// registers and waits slowed the traversal of every ray: docs/results/field-at-ray-cost.md).
struct ProbeRayHit {
  vec3 weight;      // what the arriving irradiance is multiplied by (albedo, energy
                    // conservation, glass crossed); zero: nothing to add
  uint normal_oct;  // shading normal on the side the ray sees (pack_normal)
};

// Adaptive rays: what a probe's blends measured (field_blend.comp).
struct ProbeDrift {
  vec4 drift;   // x: mean luminance, yzw: mean direction; changes relative to the probe's size
  float usual;  // the usual size of one update's change
  float pad0;
  float pad1;
  float pad2;
};

// An SH field's probe: radiance projected on the nine real SH functions of bands 0-2
// (shaders/common/sh.glsl gives their order), RGB each.
struct ShProbe {
  vec3 coefficients[9];
};

// The split update only (field_trace_surfels, then field_shade): the surface a ray found,
// kept between the two passes. The fused update (field_trace) shades where it traces.
struct ProbeSurfel {
  vec3 position;   // hit point
  float distance;  // hit distance; max_ray_distance on a miss
  vec3 albedo;
  uint normal_oct;  // shading normal on the side the ray sees
  vec3 emission;
  uint flags;  // kRay*
  uint geometric_normal_oct;
};

struct FieldConstants {
  vec3 origin;
  uint rays_per_probe;  // shaded and blended
  vec3 spacing;
  uint fixed_rays;  // traced first, never rotated, never blended
  ivec3 counts;
  uint probe_count;
  uint irradiance_texels;
  uint distance_texels;
  uint tiles_per_row;
  uint update_index;
  vec2 irradiance_atlas_size;  // texels
  vec2 distance_atlas_size;    // texels
  float hysteresis;
  float distance_hysteresis;
  float change_threshold;
  float new_distribution_threshold;
  float irradiance_gamma;
  float distance_exponent;
  float backface_distance_scale;
  float self_shadow_bias;
  float energy_conservation;
  float weight_crush_threshold;
  float max_ray_distance;
  float max_visibility_distance;  // distances are clamped here: 1.5 x the cell diagonal
  mat4 ray_rotation;              // this update's random rotation of the blended rays
  uint direct_mode;               // how probe-ray hits get direct light (frame_data kDirect*)
  float probe_offset_limit;       // relocation keeps |offset| <= limit x spacing per axis
  float min_frontface_distance;   // relocation keeps probes this far from front faces
  float backface_threshold;       // more back-face hits than this fraction: inside geometry
  uint emitter_samples;           // > 0: probe rays sample emitters and carry no emission
  uint basis;                     // kFieldBasis*
  float sh_band1;                 // SH fields: A_1 / pi x window of band 1 (shaders/common/sh.glsl)
  float sh_band2;                 // the same for band 2
  uint probe_bounces;             // > 0: probe-ray hits trace paths this long, not the field
  // The grid as a 3D circular buffer (a scrolling field, docs/cascades.md): the probe at grid
  // coordinate c (from origin) lives in the slot of coordinate (c + scroll) mod counts, each
  // axis in [0, counts). Zero for a field that never scrolled.
  ivec3 scroll;
  // --- Volumes (docs/cascades.md): a field is one or more grids ("volumes"), whose probes are
  // numbered one after another (the slots of one set of arrays and atlases); every volume has
  // its own constants (FieldBlock holds one per volume, finest first). The fields above that are
  // not the grid's (rays, texels, blending, sampling) are the same in every volume's; shaders
  // read the grid's (`field_grid`: origin, spacing, counts, scroll, first_probe,
  // max_visibility_distance, min_frontface_distance, blend_*) from the volume they work on and
  // the rest (`field`) from volume 0.
  uint first_probe;   // the volume's first slot
  uint volume_count;  // volumes of the field (the same in every volume's constants)
  // Where this volume's weight in a blend across volumes is 1: a box that the weight leaves over
  // one cell (blend_cell per axis) towards its faces. A tracking volume's box is centred on the
  // tracked camera (2021 paper sec. 7.3: a plane that leapfrogs does not change any weight).
  vec3 blend_min;
  vec3 blend_max;
  vec3 blend_cell;
  // --- Adaptive rays (IrradianceFieldParams::settle_threshold; docs/adaptive-rays.md): the
  // lighting passes of an adaptive update (FieldDispatch::skip_settled) take a probe of their
  // window only when it is hot, has no history, or its probe-list entry lies in the maintenance
  // slice [maintenance_start, maintenance_start + maintenance_count) of the list (wrapping).
  float settle_threshold;  // a probe whose drift exceeds this is hot (kDriftWeight)
  uint hot_updates;        // heat a probe gets when its change exceeds settle_threshold
  uint maintenance_start;
  uint maintenance_count;
  uint pad0;
};

// Adaptive rays (docs/adaptive-rays.md): a probe's drift follows its change in each update it
// is traced (how far the update's estimate of its irradiance lies from its history, in low
// orders, relative to their size: field_blend.comp) with this weight, so noise averages out
// over a few updates while a history that has not caught up keeps it large; its usual change
// follows the change's size with the second weight. Noise alone leaves the drift's size near
// sqrt(w / (2 - w)) = 0.38 of the usual change, a gap the history has not closed near all of
// it: a drift above kDriftOverUsual x the usual change (and settle_threshold) is a gap.
DDGI_CONST float kDriftWeight = 0.25;
DDGI_CONST float kUsualWeight = 0.1;
DDGI_CONST float kDriftOverUsual = 0.6;
// Changes are taken relative to at least this fraction of the brightest probe's irradiance: a
// closed room that light reaches only as 1e-5 of the lit one's drifts for a long time, unseen.
DDGI_CONST float kDriftFloor = 1e-3;

// At most this many volumes per field (cascades and static volumes).
DDGI_CONST uint kMaxFieldVolumes = 8u;

// What the probe-management kernel does this dispatch (FieldDispatch::mode).
DDGI_CONST uint kProbeModeRelocate = 0u;  // move probes out of geometry and off front faces
DDGI_CONST uint kProbeModeClassify = 1u;  // write each probe's state from its fixed rays
DDGI_CONST uint kProbeModeStart = 2u;     // a probe that entered a scrolled volume: on its grid
                                          // point, no history, Vigilant until classified

// Push constants of the linear (one invocation per item) field kernels. The probes a dispatch
// works on are a window of the probe list: list[(list_start + i) % list_size].
struct FieldDispatch {
  uint count;         // invocations in this dispatch
  uint row_width;     // invocations per row when the dispatch is folded into 2D
  uint list_start;    // first entry of the window
  uint list_size;     // entries in the probe list (the window wraps around)
  uint per_probe;     // invocations per probe (rays, texels, border texels)
  uint first_ray;     // ray index of the first ray a tracing dispatch handles
  uint mode;          // kProbeMode* (relocate/classify kernel); the query kernel: kQueryBlended
                      // or kQueryVolume0 + v (volume v alone)
  uint skip_settled;  // 1: the lighting passes of an adaptive update (FieldConstants)
};

// The query kernel (tests, the RPC, scripted checks): field irradiance at given points, blended
// over the volumes as frames sample it, or from one volume alone (FieldDispatch::mode).
DDGI_CONST uint kQueryBlended = 0;
DDGI_CONST uint kQueryVolume0 = 1;
DDGI_CONST uint kFieldQuerySet = 1;
DDGI_CONST uint kFieldQueryBindingQueries = 0;  // FieldQuery per point
DDGI_CONST uint kFieldQueryBindingAnswers = 1;  // vec4 per point: irradiance M (rgb), 0

struct FieldQuery {
  vec3 position;
  float pad0;
  vec3 normal;  // unit
  float pad1;
  vec3 to_viewer;  // unit; the self-shadow bias leans this way
  float pad2;
};

#ifdef __cplusplus
// C++ only: how the constants above fit together.
static_assert(kProbeStateMask == 0xFFu << kProbeStateShift && kProbeStateCount <= 0xFFu);
static_assert((kProbeStateMask & kProbeResetHistory) == 0);
static_assert((kProbeHeatMask & (kProbeStateMask | kProbeResetHistory)) == 0);

// C++ only: the byte layout GLSL gives these structs (scalar block layout), member by member, so
// that the C++ and GLSL views of a struct cannot drift apart. A failure means a struct changed:
// check that the GLSL side agrees (same header), then update the numbers here.
static_assert(sizeof(ProbeState) == 16);
static_assert(offsetof(ProbeState, offset) == 0);
static_assert(offsetof(ProbeState, flags) == 12);

static_assert(sizeof(ProbeRay) == 16);
static_assert(offsetof(ProbeRay, radiance) == 0);
static_assert(offsetof(ProbeRay, distance) == 12);

static_assert(sizeof(ProbeDrift) == 32);
static_assert(offsetof(ProbeDrift, drift) == 0);
static_assert(offsetof(ProbeDrift, usual) == 16);

static_assert(sizeof(ShProbe) == 108);
static_assert(offsetof(ShProbe, coefficients) == 0);

static_assert(sizeof(ProbeSurfel) == 52);
static_assert(offsetof(ProbeSurfel, position) == 0);
static_assert(offsetof(ProbeSurfel, distance) == 12);
static_assert(offsetof(ProbeSurfel, albedo) == 16);
static_assert(offsetof(ProbeSurfel, normal_oct) == 28);
static_assert(offsetof(ProbeSurfel, emission) == 32);
static_assert(offsetof(ProbeSurfel, flags) == 44);
static_assert(offsetof(ProbeSurfel, geometric_normal_oct) == 48);

static_assert(sizeof(FieldConstants) == 304);
static_assert(offsetof(FieldConstants, origin) == 0);
static_assert(offsetof(FieldConstants, rays_per_probe) == 12);
static_assert(offsetof(FieldConstants, spacing) == 16);
static_assert(offsetof(FieldConstants, fixed_rays) == 28);
static_assert(offsetof(FieldConstants, counts) == 32);
static_assert(offsetof(FieldConstants, probe_count) == 44);
static_assert(offsetof(FieldConstants, irradiance_texels) == 48);
static_assert(offsetof(FieldConstants, distance_texels) == 52);
static_assert(offsetof(FieldConstants, tiles_per_row) == 56);
static_assert(offsetof(FieldConstants, update_index) == 60);
static_assert(offsetof(FieldConstants, irradiance_atlas_size) == 64);
static_assert(offsetof(FieldConstants, distance_atlas_size) == 72);
static_assert(offsetof(FieldConstants, hysteresis) == 80);
static_assert(offsetof(FieldConstants, distance_hysteresis) == 84);
static_assert(offsetof(FieldConstants, change_threshold) == 88);
static_assert(offsetof(FieldConstants, new_distribution_threshold) == 92);
static_assert(offsetof(FieldConstants, irradiance_gamma) == 96);
static_assert(offsetof(FieldConstants, distance_exponent) == 100);
static_assert(offsetof(FieldConstants, backface_distance_scale) == 104);
static_assert(offsetof(FieldConstants, self_shadow_bias) == 108);
static_assert(offsetof(FieldConstants, energy_conservation) == 112);
static_assert(offsetof(FieldConstants, weight_crush_threshold) == 116);
static_assert(offsetof(FieldConstants, max_ray_distance) == 120);
static_assert(offsetof(FieldConstants, max_visibility_distance) == 124);
static_assert(offsetof(FieldConstants, ray_rotation) == 128);
static_assert(offsetof(FieldConstants, direct_mode) == 192);
static_assert(offsetof(FieldConstants, probe_offset_limit) == 196);
static_assert(offsetof(FieldConstants, min_frontface_distance) == 200);
static_assert(offsetof(FieldConstants, backface_threshold) == 204);
static_assert(offsetof(FieldConstants, emitter_samples) == 208);
static_assert(offsetof(FieldConstants, basis) == 212);
static_assert(offsetof(FieldConstants, sh_band1) == 216);
static_assert(offsetof(FieldConstants, sh_band2) == 220);
static_assert(offsetof(FieldConstants, probe_bounces) == 224);
static_assert(offsetof(FieldConstants, scroll) == 228);
static_assert(offsetof(FieldConstants, first_probe) == 240);
static_assert(offsetof(FieldConstants, volume_count) == 244);
static_assert(offsetof(FieldConstants, blend_min) == 248);
static_assert(offsetof(FieldConstants, blend_max) == 260);
static_assert(offsetof(FieldConstants, blend_cell) == 272);
static_assert(offsetof(FieldConstants, settle_threshold) == 284);
static_assert(offsetof(FieldConstants, hot_updates) == 288);
static_assert(offsetof(FieldConstants, maintenance_start) == 292);
static_assert(offsetof(FieldConstants, maintenance_count) == 296);
static_assert(offsetof(FieldConstants, pad0) == 300);

static_assert(sizeof(FieldDispatch) == 32);
static_assert(offsetof(FieldDispatch, count) == 0);
static_assert(offsetof(FieldDispatch, row_width) == 4);
static_assert(offsetof(FieldDispatch, list_start) == 8);
static_assert(offsetof(FieldDispatch, list_size) == 12);
static_assert(offsetof(FieldDispatch, per_probe) == 16);
static_assert(offsetof(FieldDispatch, first_ray) == 20);
static_assert(offsetof(FieldDispatch, mode) == 24);
static_assert(offsetof(FieldDispatch, skip_settled) == 28);

static_assert(sizeof(FieldQuery) == 48);
static_assert(offsetof(FieldQuery, position) == 0);
static_assert(offsetof(FieldQuery, pad0) == 12);
static_assert(offsetof(FieldQuery, normal) == 16);
static_assert(offsetof(FieldQuery, pad1) == 28);
static_assert(offsetof(FieldQuery, to_viewer) == 32);
static_assert(offsetof(FieldQuery, pad2) == 44);
#endif

DDGI_NAMESPACE_END

#endif
