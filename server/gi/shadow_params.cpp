#include "gi/shadow_params.h"

#include <algorithm>
#include <cmath>

#include "gi/probe_grid.h"
#include "shared/shadow_field_data.h"

namespace ddgi {
namespace {

constexpr int kMaxCountPerAxis = 256;
constexpr uint64_t kMaxProbes = 1'048'576;

}  // namespace

const ParamTable<ShadowFieldParams>& shadow_param_table() {
  using P = ShadowFieldParams;
  // The order is that of --shadow-field help and of the RPC's parameter list.
  static const ParamTable<P> table(
      "shadow field parameter", "shadow field ", grid_params<P>(kMaxCountPerAxis, kMaxProbes),
      {
          param::number("rays_per_probe", &P::rays_per_probe, 1, 1024,
                        "probe rays per probe per update"),
          param::number("max_lights", &P::max_lights, 1, gpu::kShadowMaxLights,
                        "lights kept in the atlas (first in scene order)"),
          param::choice("overflow", &P::overflow,
                        {{"shadow-rays", ShadowOverflow::kTracedShadows},
                         {"unshadowed", ShadowOverflow::kUnshadowed}},
                        "lights past max_lights"),
          param::flag("split_update", &P::split_update, param::BoolWords::kOnOff,
                      "shadow rays one update after their probe rays (thesis)"),
          param::number("max_ray_distance", &P::max_ray_distance, 1e-30f, 1e30f,
                        "longer probe rays see nothing"),
          param::number("ao_distance", &P::ao_distance, 1e-30f, 1e30f,
                        "longer AO rays count as open sky"),
          param::number("texels", &P::texels, 4, 64, "octahedral map side"),
          param::number("hysteresis", &P::hysteresis, 0.0f, 0.999f, "history weight per update"),
          param::number("visibility_exponent", &P::visibility_exponent, 1.0f, 1000.0f,
                        "power-cosine exponent of the visibility blend"),
          param::number("distance_exponent", &P::distance_exponent, 1.0f, 1000.0f,
                        "power-cosine exponent of the distance blend"),
          param::number("backface_distance_scale", &P::backface_distance_scale, 0.0f, 1.0f,
                        "back-face distance factor"),
          param::choice("weighting", &P::weighting,
                        {{"cosine", ShadowWeighting::kCosine}, {"wrap", ShadowWeighting::kWrap}},
                        "probe weights when sampling"),
          param::number("normal_bias", &P::normal_bias, 0.0f, 1.0f,
                        "shading-point offset along the normal (x spacing)"),
          param::number("view_bias", &P::view_bias, 0.0f, 1.0f,
                        "shading-point offset towards the viewer (x spacing)"),
          param::number("sharpening", &P::sharpening, 1.0f, 16.0f,
                        "power applied to sampled visibility"),
          param::number("weight_crush_threshold", &P::weight_crush_threshold, 0.0f, 1.0f,
                        "probe weights below are crushed"),
          param::number("seed", &P::seed, "seed of the ray rotations and jitter"),
      });
  return table;
}

template class ParamTable<ShadowFieldParams>;

uint64_t probe_count(const ShadowFieldParams& p) {
  return grid_probe_count(p.counts);
}

Status validate(const ShadowFieldParams& p) {
  DDGI_TRY(shadow_param_table().check(p));
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
