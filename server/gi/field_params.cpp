#include "gi/field_params.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "gi/probe_grid.h"
#include "shared/field_data.h"

namespace ddgi {
namespace {

constexpr int kMaxCountPerAxis = 512;
constexpr uint64_t kMaxProbes = 4'194'304;

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

template <typename T>
Status in_range(const char* name, T value, T min, T max) {
  if (!(value >= min && value <= max)) {
    std::ostringstream out;
    out << name << " must be in [" << min << ", " << max << "] (got " << value << ")";
    return invalid_argument(out.str());
  }
  return ok_status();
}

}  // namespace

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
  return grid_probe_count(p.counts);
}

Status validate(const IrradianceFieldParams& p) {
  if (!finite(p.origin)) return invalid_argument("origin must be finite");
  if (!finite(p.spacing) || !(p.spacing.x > 0.0f && p.spacing.y > 0.0f && p.spacing.z > 0.0f)) {
    return invalid_argument("spacing must be finite and > 0 on every axis");
  }
  for (int axis = 0; axis < 3; ++axis) {
    DDGI_TRY(in_range(axis == 0   ? "counts.x"
                      : axis == 1 ? "counts.y"
                                  : "counts.z",
                      p.counts[axis], 1, kMaxCountPerAxis));
  }
  if (probe_count(p) > kMaxProbes) {
    return invalid_argument("counts give " + std::to_string(probe_count(p)) + " probes; at most " +
                            std::to_string(kMaxProbes) + " are allowed");
  }
  DDGI_TRY(in_range("rays_per_probe", p.rays_per_probe, 1u, 1024u));
  DDGI_TRY(in_range("fixed_rays", p.fixed_rays, 0u, 256u));
  DDGI_TRY(in_range("max_ray_distance", p.max_ray_distance, 1e-30f, 1e30f));
  DDGI_TRY(in_range("irradiance_texels", p.irradiance_texels, 4u, 32u));
  DDGI_TRY(in_range("distance_texels", p.distance_texels, 4u, 64u));
  DDGI_TRY(in_range("hysteresis", p.hysteresis, 0.0f, 0.999f));
  DDGI_TRY(in_range("distance_hysteresis", p.distance_hysteresis, 0.0f, 0.999f));
  DDGI_TRY(in_range("change_threshold", p.change_threshold, 0.0f, 1.0f));
  DDGI_TRY(in_range("new_distribution_threshold", p.new_distribution_threshold, 0.0f, 1.0f));
  DDGI_TRY(in_range("irradiance_gamma", p.irradiance_gamma, 1.0f, 10.0f));
  DDGI_TRY(in_range("distance_exponent", p.distance_exponent, 1.0f, 100.0f));
  DDGI_TRY(in_range("backface_distance_scale", p.backface_distance_scale, 0.0f, 1.0f));
  DDGI_TRY(in_range("self_shadow_bias", p.self_shadow_bias, 0.0f, 2.0f));
  DDGI_TRY(in_range("energy_conservation", p.energy_conservation, 0.0f, 1.0f));
  DDGI_TRY(in_range("weight_crush_threshold", p.weight_crush_threshold, 0.0f, 1.0f));
  DDGI_TRY(in_range("relocation_iterations", p.relocation_iterations, 0u, 16u));
  DDGI_TRY(in_range("emitter_samples", p.emitter_samples, 0u, 64u));
  DDGI_TRY(in_range("probe_offset_limit", p.probe_offset_limit, 0.0f, 0.49f));
  DDGI_TRY(in_range("min_frontface_distance", p.min_frontface_distance, 0.0f, 0.5f));
  DDGI_TRY(in_range("backface_threshold", p.backface_threshold, 1e-6f, 1.0f));
  if ((p.relocation_iterations > 0 || p.classification) && p.fixed_rays < 8) {
    return invalid_argument("relocation and classification need fixed_rays >= 8 (got " +
                            std::to_string(p.fixed_rays) +
                            "); set relocation_iterations=0 and classification=false "
                            "to run without fixed rays");
  }
  const uint64_t rays_per_probe_total = p.rays_per_probe + p.fixed_rays;
  if (p.max_rays_per_update != 0 && p.max_rays_per_update < rays_per_probe_total) {
    return invalid_argument("max_rays_per_update must be 0 (no cap) or at least one probe's " +
                            std::to_string(rays_per_probe_total) + " rays (got " +
                            std::to_string(p.max_rays_per_update) + ")");
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
  const SquareTiling tiling = square_tiling(probe_count(p));
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

IrradianceFieldParams default_field_params(const Scene& scene) {
  if (scene.probe_grid) {
    IrradianceFieldParams params;
    params.origin = scene.probe_grid->origin;
    params.spacing = scene.probe_grid->spacing;
    params.counts = scene.probe_grid->counts;
    return params;
  }
  return fit_grid_to_bounds(scene.world_bounds());
}

uint64_t field_gpu_bytes(const IrradianceFieldParams& p) {
  const uint64_t probes = probe_count(p);
  const uint64_t irradiance_tile = uint64_t(p.irradiance_texels + 2) * (p.irradiance_texels + 2);
  const uint64_t distance_tile = uint64_t(p.distance_texels + 2) * (p.distance_texels + 2);
  const uint64_t rays = probes * (p.rays_per_probe + p.fixed_rays);
  return probes * (irradiance_tile * 16 + distance_tile * 8 + sizeof(gpu::ProbeState) +
                   sizeof(uint32_t)) +
         rays * sizeof(gpu::ProbeRay) + sizeof(gpu::FieldConstants);
}

}  // namespace ddgi
