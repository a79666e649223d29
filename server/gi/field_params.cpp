#include "gi/field_params.h"

#include <algorithm>
#include <cmath>

#include "gi/light_power.h"
#include "gi/probe_grid.h"
#include "shared/field_data.h"

namespace ddgi {
namespace {

constexpr int kMaxCountPerAxis = 512;
constexpr uint64_t kMaxProbes = 4'194'304;

// static_volumes: each volume "origin/spacing/counts" in the grid entries' own text forms and
// ranges (probe_grid.h), '|' between volumes, empty for none.
ParamSpec<IrradianceFieldParams> static_volumes_param() {
  using P = IrradianceFieldParams;
  static const std::vector<ParamSpec<GridPlacement>> grid =
      grid_params<GridPlacement>(kMaxCountPerAxis, kMaxProbes);
  const std::string name = "static_volumes";
  const std::string too_many =
      name + " and cascades make more than " + std::to_string(gpu::kMaxFieldVolumes) + " volumes";
  ParamSpec<P> spec;
  spec.name = name;
  spec.help =
      "grids beside the field's, each origin/spacing/counts (e.g. "
      "0,0,0/0.25,0.25,0.25/16,8,16), '|' between them; empty: none";
  spec.parse = [name](P& p, const std::string& text) -> Status {
    std::vector<GridPlacement> volumes;
    const std::vector<std::string> pieces =
        text.empty() ? std::vector<std::string>{} : split(text, '|');
    for (size_t i = 0; i < pieces.size(); ++i) {
      const std::string what = name + "[" + std::to_string(i) + "]";
      const std::vector<std::string> parts = split(pieces[i], '/');
      if (parts.size() != grid.size()) {
        return invalid_argument(what + " must be origin/spacing/counts (got '" + pieces[i] + "')");
      }
      GridPlacement volume;
      for (size_t k = 0; k < grid.size(); ++k) {
        const Status status = grid[k].parse(volume, parts[k]);
        if (!status.ok()) return invalid_argument(what + ": " + status.error().message);
      }
      volumes.push_back(volume);
    }
    p.static_volumes = volumes;
    return ok_status();
  };
  spec.format = [](const P& p) {
    std::string text;
    for (const GridPlacement& volume : p.static_volumes) {
      if (!text.empty()) text += "|";
      for (size_t k = 0; k < grid.size(); ++k) {
        if (k > 0) text += '/';
        text += grid[k].format(volume);
      }
    }
    return text;
  };
  spec.check = [name, too_many](const P& p, const std::string& prefix) -> Status {
    for (size_t i = 0; i < p.static_volumes.size(); ++i) {
      for (const ParamSpec<GridPlacement>& entry : grid) {
        DDGI_TRY(entry.check(p.static_volumes[i], prefix + name + "[" + std::to_string(i) + "] "));
      }
    }
    if (p.cascades + p.static_volumes.size() <= gpu::kMaxFieldVolumes) return ok_status();
    return invalid_argument(prefix + too_many + " (" + std::to_string(p.static_volumes.size()) +
                            " and " + std::to_string(p.cascades) + ")");
  };
  // One volume made of each grid entry's own cases, then none, and one volume too many.
  for (const ParamSpec<GridPlacement>& entry : grid) {
    for (const ParamExample<GridPlacement>& example : entry.examples) {
      GridPlacement volume;
      example.apply(volume);
      spec.examples.push_back({example.value, [volume](P& p) { p.static_volumes = {volume}; },
                               example.refusal.empty() ? "" : name + "[0] " + example.refusal});
    }
  }
  spec.examples.push_back({"", [](P& p) { p.static_volumes.clear(); }, ""});
  spec.examples.push_back({std::to_string(gpu::kMaxFieldVolumes) + " volumes",
                           [](P& p) { p.static_volumes.resize(gpu::kMaxFieldVolumes); }, too_many});
  return spec;
}

}  // namespace

const ParamTable<IrradianceFieldParams>& field_param_table() {
  using P = IrradianceFieldParams;
  // The order is that of --field help and of the RPC's parameter list.
  static const ParamTable<P> table(
      "field parameter", "", grid_params<P>(kMaxCountPerAxis, kMaxProbes),
      {
          param::flag("track_camera", &P::track_camera, param::BoolWords::kTrueFalse,
                      "the grid scrolls with the camera in whole cells"),
          param::number("cascades", &P::cascades, 1, int(gpu::kMaxFieldVolumes),
                        "volumes of `counts` probes around one centre, each coarser"),
          param::number("cascade_spacing_ratio", &P::cascade_spacing_ratio, 1.0f, 16.0f,
                        "spacing of each cascade over the previous one's"),
          static_volumes_param(),
          param::number("rays_per_probe", &P::rays_per_probe, 1, 1024,
                        "blended rays per probe per update"),
          param::number("fixed_rays", &P::fixed_rays, 0, 256,
                        "unrotated rays for relocation/classification"),
          param::number("max_ray_distance", &P::max_ray_distance, 1e-30f, 1e30f,
                        "longer rays are misses"),
          param::choice("basis", &P::basis,
                        {{"octahedral", ProbeBasis::kOctahedral}, {"sh", ProbeBasis::kSh}},
                        "what probes store: octahedral maps or L2 SH"),
          param::number("sh_window", &P::sh_window, 0.0f, 64.0f,
                        "SH Hanning window width (0: none)"),
          param::number("irradiance_texels", &P::irradiance_texels, 4, 32, "irradiance map side"),
          param::number("distance_texels", &P::distance_texels, 4, 64, "distance map side"),
          param::number("hysteresis", &P::hysteresis, 0.0f, 0.999f, "history weight per update"),
          param::number("distance_hysteresis", &P::distance_hysteresis, 0.0f, 0.999f,
                        "history weight of distances"),
          param::number("change_threshold", &P::change_threshold, 0.0f, 1.0f,
                        "relative change that lowers hysteresis"),
          param::number("new_distribution_threshold", &P::new_distribution_threshold, 0.0f, 1.0f,
                        "relative change that drops history"),
          param::number("irradiance_gamma", &P::irradiance_gamma, 1.0f, 10.0f,
                        "perceptual encoding exponent"),
          param::number("distance_exponent", &P::distance_exponent, 1.0f, 100.0f,
                        "power-cosine exponent of distances"),
          param::number("backface_distance_scale", &P::backface_distance_scale, 0.0f, 1.0f,
                        "back-face distance factor"),
          param::number("self_shadow_bias", &P::self_shadow_bias, 0.0f, 2.0f, "2021 paper's B"),
          param::number(
              "probe_bounces", &P::probe_bounces, 0, 64,
              "path vertices after a probe-ray hit, then the field (0: the field at the hit)"),
          param::number("energy_conservation", &P::energy_conservation, 0.0f, 1.0f,
                        "irradiance feedback factor"),
          param::number("weight_crush_threshold", &P::weight_crush_threshold, 0.0f, 1.0f,
                        "weights below are crushed"),
          param::number("relocation_iterations", &P::relocation_iterations, 0, 16,
                        "relocation passes (0: no relocation)"),
          param::flag("classification", &P::classification, param::BoolWords::kTrueFalse,
                      "Off/Sleeping/Vigilant/Awake states, trace active probes only"),
          param::number("probe_offset_limit", &P::probe_offset_limit, 0.0f, 0.49f,
                        "relocation limit, fraction of spacing"),
          param::number("min_frontface_distance", &P::min_frontface_distance, 0.0f, 0.5f,
                        "relocation clearance, fraction of spacing"),
          param::number("backface_threshold", &P::backface_threshold, 1e-6f, 1.0f,
                        "back-face fraction meaning inside"),
          // Its limit depends on rays_per_probe: validate() states it.
          param::number("max_rays_per_update", &P::max_rays_per_update,
                        "probe rays per update, 0: no cap, else >= one probe's rays"),
          param::number("settle_threshold", &P::settle_threshold, 0.0f, 1.0f,
                        "adaptive rays: mean texel change below which a probe settles (0: off)"),
          param::number("hot_updates", &P::hot_updates, 1, 255,
                        "adaptive rays: updates a changing probe stays traced"),
          param::number("maintenance_rate", &P::maintenance_rate, 0.001f, 1.0f,
                        "adaptive rays: fraction of settled probes traced per update"),
          param::number("emitter_samples", &P::emitter_samples, 0, 64,
                        "emitter samples per pixel and probe-ray hit (0: emitters via the field)"),
          param::number("pixel_paths", &P::pixel_paths, 0, 64,
                        "paths per pixel that trace its indirect light (0: the field at it)"),
          param::number("pixel_path_vertices", &P::pixel_path_vertices, 1, 64,
                        "vertices of each path per pixel before it reads the field"),
          param::choice("probe_direct", &P::probe_direct, "frame",
                        {{"shadow-rays", DirectMode::kTracedShadows},
                         {"unshadowed", DirectMode::kUnshadowed},
                         {"shadow-field", DirectMode::kShadowField},
                         {"ao", DirectMode::kAmbientOcclusion}},
                        "direct light at probe-ray hits (frame: the frame's mode)"),
          param::number("seed", &P::seed, "seed of the random ray rotations"),
      });
  return table;
}

template class ParamTable<IrradianceFieldParams>;

float visibility_range(glm::vec3 spacing) {
  const double diagonal = std::sqrt(double(spacing.x) * spacing.x + double(spacing.y) * spacing.y +
                                    double(spacing.z) * spacing.z);
  return static_cast<float>(std::min(1.5 * diagonal, 1e17));
}

DirectMode shadow_field_mode(DirectMode frame_mode, const IrradianceFieldParams* field) {
  if (uses_shadow_field(frame_mode) || !field) return frame_mode;
  return field->probe_direct.value_or(frame_mode);
}

uint64_t probe_count(const IrradianceFieldParams& p) {
  uint64_t probes = grid_probe_count(p.counts) * p.cascades;
  for (const GridPlacement& volume : p.static_volumes) probes += grid_probe_count(volume.counts);
  return probes;
}

std::vector<FieldVolume> field_volumes(const IrradianceFieldParams& p) {
  std::vector<FieldVolume> volumes;
  const glm::vec3 half_cells = 0.5f * glm::vec3(p.counts - 1);
  const glm::vec3 centre = p.origin + p.spacing * half_cells;
  float scale = 1.0f;
  for (uint32_t v = 0; v < p.cascades; ++v) {
    FieldVolume volume;
    volume.spacing = p.spacing * scale;
    volume.origin = v == 0 ? p.origin : centre - volume.spacing * half_cells;
    volume.counts = p.counts;
    volume.cascade = v;
    volumes.push_back(volume);
    scale *= p.cascade_spacing_ratio;
  }
  for (uint32_t s = 0; s < p.static_volumes.size(); ++s) {
    const GridPlacement& placement = p.static_volumes[s];
    volumes.push_back({placement.origin, placement.spacing, placement.counts, 0, 0, s});
  }
  auto coarseness = [](const FieldVolume& v) {
    return std::max({v.spacing.x, v.spacing.y, v.spacing.z});
  };
  std::stable_sort(volumes.begin(), volumes.end(), [&](const FieldVolume& a, const FieldVolume& b) {
    return coarseness(a) < coarseness(b);
  });
  uint64_t first = 0;
  for (FieldVolume& volume : volumes) {
    volume.first_probe = static_cast<uint32_t>(first);
    first += grid_probe_count(volume.counts);
  }
  return volumes;
}

uint32_t probe_slot(glm::ivec3 counts, glm::ivec3 scroll, glm::ivec3 coord) {
  const glm::ivec3 s = (coord + scroll) % counts;
  return uint32_t(s.x) + uint32_t(counts.x) * (uint32_t(s.y) + uint32_t(counts.y) * uint32_t(s.z));
}

glm::ivec3 probe_coord(glm::ivec3 counts, glm::ivec3 scroll, uint32_t slot) {
  const glm::ivec3 s(int(slot % uint32_t(counts.x)),
                     int(slot / uint32_t(counts.x) % uint32_t(counts.y)),
                     int(slot / uint32_t(counts.x) / uint32_t(counts.y)));
  return (s - scroll + counts) % counts;
}

glm::ivec3 tracking_scroll(const FieldVolume& p, glm::vec3 camera) {
  const glm::vec3 centre = p.origin + 0.5f * p.spacing * glm::vec3(p.counts - 1);
  const glm::vec3 cells = (camera - centre) / p.spacing;
  if (glm::any(glm::isnan(cells)) || glm::any(glm::isinf(cells))) return glm::ivec3(0);
  // Truncation: a cell or more away on an axis moves the grid; less never does.
  const glm::vec3 limit(float(1 << 30));
  return glm::ivec3(glm::clamp(glm::trunc(cells), -limit, limit));
}

Status validate(const IrradianceFieldParams& p) {
  DDGI_TRY(field_param_table().check(p));
  if (probe_count(p) > kMaxProbes) {
    return invalid_argument("cascades=" + std::to_string(p.cascades) + " of " +
                            std::to_string(grid_probe_count(p.counts)) + " probes and " +
                            std::to_string(p.static_volumes.size()) + " static volume(s) make " +
                            std::to_string(probe_count(p)) + " probes; at most " +
                            std::to_string(kMaxProbes) +
                            " fit (use fewer cascades, volumes or probes)");
  }
  if ((p.relocation_iterations > 0 || p.classification) && p.fixed_rays < 8) {
    return invalid_argument("relocation and classification need fixed_rays >= 8 (got " +
                            std::to_string(p.fixed_rays) +
                            "); set relocation_iterations=0 and classification=false "
                            "to run without fixed rays");
  }
  if (p.max_rays_per_update != 0 && p.max_rays_per_update < p.rays_per_probe) {
    return invalid_argument("max_rays_per_update must be 0 (no cap) or at least one probe's " +
                            std::to_string(p.rays_per_probe) + " rays (got " +
                            std::to_string(p.max_rays_per_update) + ")");
  }
  if (p.settle_threshold > 0.0f && p.basis != ProbeBasis::kOctahedral) {
    return invalid_argument(
        "settle_threshold > 0 (adaptive rays) needs basis=octahedral: an SH probe's change is "
        "not measured yet; set settle_threshold=0");
  }
  const AtlasLayout layout = atlas_layout(p);
  const glm::uvec2 largest = glm::max(layout.irradiance_size, layout.distance_size);
  if (largest.x > gpu::kMaxAtlasDimension || largest.y > gpu::kMaxAtlasDimension) {
    return invalid_argument("counts give " + std::to_string(probe_count(p)) +
                            " probes, whose atlas would be " + std::to_string(largest.x) + "x" +
                            std::to_string(largest.y) + " texels; at most " +
                            std::to_string(gpu::kMaxAtlasDimension) +
                            " per side fit (use fewer probes or smaller texel counts)");
  }
  return ok_status();
}

AtlasLayout atlas_layout(const IrradianceFieldParams& p) {
  AtlasLayout layout;
  // SH fields keep one tile of each atlas only so that the sampling set stays complete.
  const SquareTiling tiling = square_tiling(p.basis == ProbeBasis::kSh ? 1 : probe_count(p));
  layout.tiles_per_row = tiling.tiles_per_row;
  layout.rows = tiling.rows;
  const uint32_t irradiance_tile = p.irradiance_texels + 2 * gpu::kAtlasBorder;
  const uint32_t distance_tile = p.distance_texels + 2 * gpu::kAtlasBorder;
  layout.irradiance_size = {layout.tiles_per_row * irradiance_tile, layout.rows * irradiance_tile};
  layout.distance_size = {layout.tiles_per_row * distance_tile, layout.rows * distance_tile};
  return layout;
}

IrradianceFieldParams fit_grid_to_bounds(const Bounds& bounds, uint32_t target_probes,
                                         IrradianceFieldParams base) {
  const GridFitStart fit = start_grid_fit(bounds);
  if (fit.single) return placed(base, *fit.single);
  const glm::vec3 extent = fit.extent;
  // Flat axes (thinner than 1% of the largest) get one probe layer.
  const float volume = fit.used.x * fit.used.y * fit.used.z;
  const float spacing = std::cbrt(volume / float(std::max(target_probes, 1u)));
  for (int axis = 0; axis < 3; ++axis) {
    const int count = static_cast<int>(std::lround(extent[axis] / spacing));
    base.counts[axis] = std::clamp(count, 1, kMaxCountPerAxis);
    base.spacing[axis] = extent[axis] > 0.0f ? extent[axis] / float(base.counts[axis]) : spacing;
    // Cell-centred: probe i sits at min + (i + 0.5) * spacing.
    base.origin[axis] = bounds.min[axis] + 0.5f * base.spacing[axis];
    if (extent[axis] <= 0.0f) base.origin[axis] = bounds.min[axis];
  }
  return base;
}

namespace {

// The default grid: fitted to the whole scene, unless that spaces its probes wider than the
// objects standing on a ground plane are large (lights_punctual: one layer 4.6 m apart over a
// 157 m plane, none near its 2 m cube; its indirect view came out at 0.12 of the reference).
// Then it covers the objects and the ground within their own extent around them. A ground the
// whole grid still resolves keeps it (box_on_floor: 0.5 m over an 8 m floor, a 1 m box).
IrradianceFieldParams fit_default_grid(const Scene& scene) {
  const Bounds world = scene.world_bounds();
  IrradianceFieldParams whole = fit_grid_to_bounds(world);
  const std::optional<Bounds> objects = scene.bounds_without_ground();
  if (!objects) return whole;
  const glm::vec3 extent = objects->extent();
  const float reach = std::max({extent.x, extent.y, extent.z});
  const float spacing = std::max({whole.spacing.x, whole.spacing.y, whole.spacing.z});
  if (!(spacing > reach)) return whole;
  const Bounds near{glm::max(world.min, objects->min - glm::vec3(reach)),
                    glm::min(world.max, objects->max + glm::vec3(reach))};
  return fit_grid_to_bounds(near);
}

}  // namespace

IrradianceFieldParams default_field_params(const Scene& scene) {
  static_assert(kMaxSceneProbeVolumes + 1 == gpu::kMaxFieldVolumes);
  IrradianceFieldParams params = scene.probe_grid
                                     ? placed(IrradianceFieldParams{}, *scene.probe_grid)
                                     : fit_default_grid(scene);
  params.static_volumes = scene.probe_volumes;
  if (emitters_worth_sampling(scene)) params.emitter_samples = kSceneEmitterSamples;
  return params;
}

uint64_t largest_map_tile_bytes(const IrradianceFieldParams& p) {
  const uint64_t irradiance_side = p.irradiance_texels + 2 * gpu::kAtlasBorder;
  const uint64_t distance_side = p.distance_texels + 2 * gpu::kAtlasBorder;
  return std::max(irradiance_side * irradiance_side * 16, distance_side * distance_side * 8);
}

uint64_t probe_ray_hit_records(const IrradianceFieldParams& p) {
  return p.probe_bounces > 0 ? 1 : probe_count(p) * (p.rays_per_probe + p.fixed_rays);
}

uint64_t field_gpu_bytes(const IrradianceFieldParams& p) {
  const uint64_t probes = probe_count(p);
  const uint64_t irradiance_tile = uint64_t(p.irradiance_texels + 2) * (p.irradiance_texels + 2);
  const uint64_t distance_tile = uint64_t(p.distance_texels + 2) * (p.distance_texels + 2);
  const uint64_t rays = probes * (p.rays_per_probe + p.fixed_rays);
  const uint64_t probe_maps = irradiance_tile * 16 + distance_tile * 8;
  const bool sh = p.basis == ProbeBasis::kSh;
  // One tile of each map for SH fields, one ShProbe for octahedral ones (atlas_layout()).
  const uint64_t maps =
      sh ? probes * sizeof(gpu::ShProbe) + probe_maps : probes * probe_maps + sizeof(gpu::ShProbe);
  // Per probe: its state and the state's host-visible copy for scrolls, two probe-list entries
  // (the active list, the probes a scroll starts) and its drift (adaptive rays, after a 16-byte
  // header); one zero tile to clear maps from. Per ray: what it brought back; and the hit
  // records (probe_ray_hit_records).
  return maps +
         probes * (2 * sizeof(gpu::ProbeState) + 2 * sizeof(uint32_t) + sizeof(gpu::ProbeDrift)) +
         sizeof(glm::vec4) + largest_map_tile_bytes(p) + rays * sizeof(gpu::ProbeRay) +
         probe_ray_hit_records(p) * sizeof(gpu::ProbeRayHit) + sizeof(gpu::FieldConstants);
}

std::array<float, 3> sh_band_scales(const IrradianceFieldParams& p) {
  auto window = [&](int band) {
    if (p.sh_window <= 0.0f) return 1.0;
    if (float(band) >= p.sh_window) return 0.0;
    return 0.5 * (1.0 + std::cos(3.14159265358979 * band / p.sh_window));
  };
  // A_l / pi: 2/3 and 1/4 (Ramamoorthi and Hanrahan 2001).
  return {1.0f, float(2.0 / 3.0 * window(1)), float(0.25 * window(2))};
}

}  // namespace ddgi
