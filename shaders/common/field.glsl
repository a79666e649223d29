// The irradiance field (descriptor set 2): probe addressing, ray directions, atlas lookups
// and the 8-probe cage query (Majercik et al. 2019/2021, Hvezda 2022 ch. 4), for both probe
// bases: octahedral maps with visibility, or SH coefficients without (DDISH-GI).
#ifndef DDGI_COMMON_FIELD_GLSL
#define DDGI_COMMON_FIELD_GLSL

#extension GL_EXT_scalar_block_layout : require

#include "common/math.glsl"
#include "shared/field_data.h"
#include "common/sh.glsl"

layout(set = kFieldSet, binding = kFieldBindingConstants, scalar) readonly buffer FieldBlock {
  FieldConstants volumes[];  // one per volume, finest first (field_data.h)
};
// `field_grid` is the grid of the volume being worked on (origin, spacing, counts, phase and
// what scales with them): a kernel that handles a probe selects the probe's volume
// (select_probe_volume), the cross-volume query selects each in turn. `field` is everything the
// volumes share, the same in each: read from volume 0.
uint field_volume = 0u;
#define field_grid volumes[field_volume]
#define field volumes[0]
layout(set = kFieldSet, binding = kFieldBindingProbes, scalar) buffer ProbeStates {
  ProbeState probe_states[];
};
layout(set = kFieldSet, binding = kFieldBindingIrradiance) uniform sampler2D irradiance_atlas;
layout(set = kFieldSet, binding = kFieldBindingDistance) uniform sampler2D distance_atlas;
layout(set = kFieldSet, binding = kFieldBindingSh, scalar) buffer ShProbes {
  ShProbe sh_probes[];
};

// --- Probe addressing ---------------------------------------------------------------------
// Probe p (a slot of the probe arrays and atlases) of the selected volume is its local slot
// s = p - first_probe = x + counts.x * (y + counts.y * z). The slot of the probe at grid
// coordinate c is c shifted by the scroll phase, per axis modulo the count (field_data.h): a
// scrolling volume moves whole planes without moving their data.
// (c + scroll) mod counts for c and scroll in [0, counts): one compare per axis instead of an
// integer division (this runs for each of the 8 probes of every field query).
ivec3 wrap_once(ivec3 c) {
  return c - field_grid.counts * ivec3(greaterThanEqual(c, field_grid.counts));
}

ivec3 probe_grid_coord(uint p) {
  const uint local = p - field_grid.first_probe;
  const uint x = local % uint(field_grid.counts.x);
  const uint yz = local / uint(field_grid.counts.x);
  const ivec3 slot =
      ivec3(int(x), int(yz % uint(field_grid.counts.y)), int(yz / uint(field_grid.counts.y)));
  return wrap_once(slot - field_grid.scroll + field_grid.counts);
}

uint probe_index(ivec3 c) {
  const ivec3 slot = wrap_once(c + field_grid.scroll);
  return field_grid.first_probe + uint(slot.x) +
         uint(field_grid.counts.x) * (uint(slot.y) + uint(field_grid.counts.y) * uint(slot.z));
}

// Makes `field_grid` the grid of the volume that owns probe p.
void select_probe_volume(uint p) {
  field_volume = 0u;
  for (uint v = 1u; v < volumes[0].volume_count; ++v) {
    if (p >= volumes[v].first_probe) field_volume = v;
  }
}

uint probe_state(uint p) {
  return (probe_states[p].flags & kProbeStateMask) >> kProbeStateShift;
}

vec3 probe_position(uint p) {
  return field_grid.origin + field_grid.spacing * vec3(probe_grid_coord(p)) + probe_states[p].offset;
}

// --- Ray directions ------------------------------------------------------------------------
// Point i of n on the spherical Fibonacci set (Keinert et al. 2015; thesis eq. 4.2-4.3).
vec3 spherical_fibonacci(uint i, uint n) {
  const float kGoldenRatio = 1.61803398875;
  const float phi = 2.0 * kPi * fract(float(i) / kGoldenRatio);
  const float z = 1.0 - (2.0 * float(i) + 1.0) / float(n);
  const float r = sqrt(clamp(1.0 - z * z, 0.0, 1.0));
  return vec3(cos(phi) * r, sin(phi) * r, z);
}

uint rays_per_probe_total() { return field.fixed_rays + field.rays_per_probe; }

// Direction of ray r of any probe: the first fixed_rays never rotate; the others are rotated
// by this update's random rotation.
vec3 probe_ray_direction(uint r) {
  if (r < field.fixed_rays) return spherical_fibonacci(r, field.fixed_rays);
  return normalize(mat3(field.ray_rotation) *
                   spherical_fibonacci(r - field.fixed_rays, field.rays_per_probe));
}

// --- Atlas addressing ---------------------------------------------------------------------
uvec2 probe_tile_origin(uint p, uint texels) {
  const uint tile = texels + 2u * kAtlasBorder;
  return uvec2(p % field.tiles_per_row, p / field.tiles_per_row) * tile;
}

// Direction of interior texel (i, j) of an octahedral map with `texels` per side.
vec3 octahedral_texel_direction(uvec2 ij, uint texels) {
  return octahedral_decode((vec2(ij) + 0.5) / float(texels) * 2.0 - 1.0);
}

// Atlas UV of direction `d` inside probe p's map (bilinear filtering stays inside the tile
// thanks to the border).
vec2 atlas_uv(uint p, vec3 d, uint texels, vec2 atlas_size) {
  const vec2 oct = octahedral_encode(d) * 0.5 + 0.5;
  const vec2 texel = vec2(probe_tile_origin(p, texels)) + float(kAtlasBorder) + oct * float(texels);
  return texel / atlas_size;
}

// --- The cage query -----------------------------------------------------------------------
// Chebyshev visibility of point `biased` from octahedral probe p's distance moments.
float chebyshev_visibility(uint p, vec3 biased, vec3 n) {
  const vec3 probe_to_point = biased - probe_position(p);
  const float r = length(probe_to_point);
  const vec2 moments = textureLod(distance_atlas,
                                  atlas_uv(p, safe_normalize(probe_to_point, n),
                                           field.distance_texels, field.distance_atlas_size),
                                  0.0)
                           .rg;
  if (r <= moments.x) return 1.0;
  const float variance = abs(moments.y - moments.x * moments.x);
  const float d = r - moments.x;
  const float chebyshev = variance / max(variance + d * d, 1e-30);
  return chebyshev * chebyshev * chebyshev;
}

// What the cage blends of probe p around normal n: octahedral irradiance at gamma 2 (2021
// paper, fig. 3: decode to gamma 2 for the blend, square after), SH irradiance linearly.
vec3 probe_blend_value(uint p, vec3 n) {
  if (field.basis == kFieldBasisSh) {
    return sh_irradiance(sh_probes[p], n, field.sh_band1, field.sh_band2);
  }
  const vec3 encoded =
      textureLod(irradiance_atlas,
                 atlas_uv(p, n, field.irradiance_texels, field.irradiance_atlas_size), 0.0)
          .rgb;
  return pow(max(encoded, vec3(0.0)), vec3(field.irradiance_gamma * 0.5));
}

// M of probe p alone around n (the probe view).
vec3 probe_irradiance(uint p, vec3 n) {
  const vec3 value = probe_blend_value(p, n);
  return field.basis == kFieldBasisOctahedral ? value * value : value;
}

// --- The cage query -----------------------------------------------------------------------
// The selected volume's M at `p` (sample_irradiance below blends the volumes).
vec3 sample_volume_irradiance(vec3 p, vec3 n, vec3 to_viewer) {
  const float min_spacing = min(field_grid.spacing.x, min(field_grid.spacing.y, field_grid.spacing.z));
  // 2021 paper, eq. 2: one bias along the normal and the view direction.
  const vec3 bias = (n * 0.2 + to_viewer * 0.8) * (0.75 * min_spacing) * field.self_shadow_bias;
  const vec3 biased = p + bias;

  const ivec3 last = field_grid.counts - 1;
  const vec3 grid = (biased - field_grid.origin) / field_grid.spacing;
  const ivec3 base = clamp(ivec3(floor(grid)), ivec3(0), max(last - 1, ivec3(0)));
  const vec3 alpha = clamp(grid - vec3(base), 0.0, 1.0);

  vec3 sum = vec3(0.0);
  float weight_sum = 0.0;
  for (uint i = 0u; i < 8u; ++i) {
    const ivec3 offset = ivec3(i & 1u, (i >> 1) & 1u, (i >> 2) & 1u);
    const ivec3 coord = min(base + offset, last);
    const uint probe = probe_index(coord);
    // Probes inside geometry see only back faces: they would darken what they touch (thesis
    // Fig. 6.2, the 2021 paper's Off state).
    if (probe_state(probe) == kProbeOff) continue;
    const vec3 probe_pos = probe_position(probe);

    // Trilinear weight; axes with one probe give all weight to it.
    const vec3 tri = mix(1.0 - alpha, alpha, vec3(offset));
    float weight = 1.0;

    // Wrap shading: probes behind the surface count less (thesis eq. 4.4 with a = 1).
    const vec3 to_probe = safe_normalize(probe_pos - p, n);
    const float wrap = (dot(to_probe, n) + 1.0) * 0.5;
    weight *= wrap * wrap + 0.2;

    // Octahedral probes know what they see (their distance moments); SH probes do not.
    if (field.basis == kFieldBasisOctahedral) weight *= chebyshev_visibility(probe, biased, n);

    // Crush tiny weights: light leaking through thin walls shows at low weights.
    weight = max(weight, 1e-6);
    const float c = field.weight_crush_threshold;
    if (weight < c) weight *= weight * weight / (c * c);

    weight *= max(tri.x * tri.y * tri.z, 0.0);

    sum += weight * probe_blend_value(probe, n);
    weight_sum += weight;
  }
  if (!(weight_sum > 0.0)) return vec3(0.0);
  const vec3 blended = sum / weight_sum;
  return sanitize_radiance(field.basis == kFieldBasisOctahedral ? blended * blended : blended);
}

// The selected volume's weight at `p`: 1 inside its blend box, falling linearly to 0 over one
// cell towards the box's faces (the 2021 paper's volume blending, sec. 7.3).
float volume_weight(vec3 p) {
  const vec3 inside = min(p - field_grid.blend_min, field_grid.blend_max - p) / field_grid.blend_cell;
  return clamp(min(inside.x, min(inside.y, inside.z)) + 1.0, 0.0, 1.0);
}

// Cosine-weighted mean radiance M (= E / pi, see field_data.h) arriving at `p` around normal
// `n`. `to_viewer`: unit direction from p to whoever looks at it (camera or probe). Volumes are
// visited finest first; each takes its weight of what the finer ones left, and the coarsest
// takes all that is left (so one volume answers everywhere, clamped at its edges, as a single
// grid does). The selected volume is kept.
vec3 sample_irradiance(vec3 p, vec3 n, vec3 to_viewer) {
  const uint count = volumes[0].volume_count;
  // One volume (every fitted field): its query alone, without the blend's weights.
  if (count == 1u) return sample_volume_irradiance(p, n, to_viewer);
  const uint selected = field_volume;
  vec3 sum = vec3(0.0);
  float left = 1.0;
  for (uint v = 0u; v < count && left > 0.0; ++v) {
    field_volume = v;
    const float w = v + 1u == count ? left : left * volume_weight(p);
    if (w > 0.0) sum += w * sample_volume_irradiance(p, n, to_viewer);
    left -= w;
  }
  field_volume = selected;
  return sum;
}

#endif
