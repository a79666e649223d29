#include "gi/shadow_params.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "gi/probe_grid.h"
#include "shared/shadow_field_data.h"

namespace ddgi {
namespace {

constexpr int kMaxCountPerAxis = 256;
constexpr uint64_t kMaxProbes = 1'048'576;

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

template <typename T>
Status in_range(const char* name, T value, T min, T max) {
  if (!(value >= min && value <= max)) {
    std::ostringstream out;
    out << "shadow field " << name << " must be in [" << min << ", " << max << "] (got " << value
        << ")";
    return invalid_argument(out.str());
  }
  return ok_status();
}

}  // namespace

uint64_t probe_count(const ShadowFieldParams& p) {
  return grid_probe_count(p.counts);
}

Status validate(const ShadowFieldParams& p) {
  if (!finite(p.origin)) return invalid_argument("shadow field origin must be finite");
  if (!finite(p.spacing) || !(p.spacing.x > 0.0f && p.spacing.y > 0.0f && p.spacing.z > 0.0f)) {
    return invalid_argument("shadow field spacing must be finite and > 0 on every axis");
  }
  const char* axes[] = {"counts.x", "counts.y", "counts.z"};
  for (int axis = 0; axis < 3; ++axis) {
    DDGI_TRY(in_range(axes[axis], p.counts[axis], 1, kMaxCountPerAxis));
  }
  if (probe_count(p) > kMaxProbes) {
    return invalid_argument("shadow field counts give " + std::to_string(probe_count(p)) +
                            " probes; at most " + std::to_string(kMaxProbes) + " are allowed");
  }
  DDGI_TRY(in_range("rays_per_probe", p.rays_per_probe, 1u, 1024u));
  DDGI_TRY(in_range("max_lights", p.max_lights, 1u, gpu::kShadowMaxLights));
  if (p.overflow != ShadowOverflow::kTracedShadows && p.overflow != ShadowOverflow::kUnshadowed) {
    return invalid_argument("shadow field overflow must be shadow-rays or unshadowed");
  }
  DDGI_TRY(in_range("max_ray_distance", p.max_ray_distance, 1e-30f, 1e30f));
  DDGI_TRY(in_range("ao_distance", p.ao_distance, 1e-30f, 1e30f));
  DDGI_TRY(in_range("texels", p.texels, 4u, 64u));
  DDGI_TRY(in_range("hysteresis", p.hysteresis, 0.0f, 0.999f));
  DDGI_TRY(in_range("visibility_exponent", p.visibility_exponent, 1.0f, 1000.0f));
  DDGI_TRY(in_range("distance_exponent", p.distance_exponent, 1.0f, 1000.0f));
  DDGI_TRY(in_range("backface_distance_scale", p.backface_distance_scale, 0.0f, 1.0f));
  if (p.weighting != ShadowWeighting::kCosine && p.weighting != ShadowWeighting::kWrap) {
    return invalid_argument("shadow field weighting must be cosine or wrap");
  }
  DDGI_TRY(in_range("normal_bias", p.normal_bias, 0.0f, 1.0f));
  DDGI_TRY(in_range("view_bias", p.view_bias, 0.0f, 1.0f));
  DDGI_TRY(in_range("sharpening", p.sharpening, 1.0f, 16.0f));
  DDGI_TRY(in_range("weight_crush_threshold", p.weight_crush_threshold, 0.0f, 1.0f));
  const ShadowAtlasLayout layout = shadow_atlas_layout(p);
  const glm::uvec2 largest = glm::max(layout.visibility_size, layout.moments_size);
  if (largest.x > gpu::kShadowMaxAtlasDimension || largest.y > gpu::kShadowMaxAtlasDimension) {
    return invalid_argument("shadow field counts give " + std::to_string(probe_count(p)) +
                            " probes, whose visibility atlas would be " +
                            std::to_string(largest.x) + "x" + std::to_string(largest.y) +
                            " texels; at most " + std::to_string(gpu::kShadowMaxAtlasDimension) +
                            " per side fit (use fewer probes, texels or max_lights)");
  }
  return ok_status();
}

ShadowAtlasLayout shadow_atlas_layout(const ShadowFieldParams& p) {
  ShadowAtlasLayout layout;
  const SquareTiling tiling = square_tiling(probe_count(p));
  layout.tiles_per_row = tiling.tiles_per_row;
  layout.tile_rows = tiling.rows;
  layout.light_groups =
      (std::max(p.max_lights, 1u) + gpu::kShadowLightsPerGroup - 1) / gpu::kShadowLightsPerGroup;
  const uint32_t tile = p.texels + 2 * gpu::kShadowAtlasBorder;
  layout.moments_size = {layout.tiles_per_row * tile, layout.tile_rows * tile};
  layout.visibility_size = {layout.moments_size.x, layout.moments_size.y * layout.light_groups};
  return layout;
}

ShadowFieldParams fit_shadow_grid(const Bounds& bounds, uint32_t target_cells,
                                  ShadowFieldParams base) {
  const GridFitStart fit = start_grid_fit(bounds);
  if (fit.single) return placed(base, *fit.single);
  const glm::vec3 used = fit.used;
  const float target = std::cbrt(used.x * used.y * used.z / float(std::max(target_cells, 1u)));
  for (int axis = 0; axis < 3; ++axis) {
    // Cell-centred over the bounds plus one layer half a cell outside each face: a surface on
    // the bounds (a floor, the top of the tallest object) has probes in front of it, which
    // cosine weighting needs. A flat axis gets one layer on each side of its plane.
    const bool flat = fit.extent[axis] <= fit.largest * 0.01f;
    const int cells = flat ? 1 : std::max(1, static_cast<int>(std::lround(used[axis] / target)));
    base.spacing[axis] = flat ? target : used[axis] / float(cells);
    base.counts[axis] = std::min(flat ? 2 : cells + 2, kMaxCountPerAxis);
    base.origin[axis] =
        bounds.center()[axis] - 0.5f * base.spacing[axis] * float(base.counts[axis] - 1);
  }
  return base;
}

uint64_t shadow_field_gpu_bytes(const ShadowFieldParams& p) {
  const ShadowAtlasLayout layout = shadow_atlas_layout(p);
  const uint64_t texels = uint64_t(layout.moments_size.x) * layout.moments_size.y +
                          uint64_t(layout.visibility_size.x) * layout.visibility_size.y;
  return texels * 16 + probe_count(p) * p.rays_per_probe * sizeof(gpu::ShadowRay) +
         sizeof(gpu::ShadowFieldConstants);
}

}  // namespace ddgi
