// What the probe grids of the irradiance field and the shadow field have in common: the probe
// count of a grid, the near-square tiling of one atlas tile per probe, and how fitting a grid to
// bounds starts, and the grid's parameters in a field's table. Each field keeps its own rules
// (cell-centred probes, or an extra outer layer).
#pragma once

#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

#include "gi/param_table.h"
#include "scene/scene.h"

namespace ddgi {

// Probes of a grid with `counts` per axis (negative counts count as 0).
uint64_t grid_probe_count(glm::ivec3 counts);

// `tiles` tiles in rows of ceil(sqrt(tiles)): an atlas about as wide as tall.
struct SquareTiling {
  uint32_t tiles_per_row = 1;
  uint32_t rows = 1;
};
SquareTiling square_tiling(uint64_t tiles);

// The start of fitting a grid to bounds. Bounds without extent (empty, or a single point) get
// one probe, at the world origin or on the point: `single` is then the whole fit. Otherwise
// `extent` is the bounds' extent per axis and `used` the extent to divide into cells, where
// axes thinner than 1% of the largest are raised to that 1% (a flat scene still gets cells).
struct GridFitStart {
  std::optional<GridPlacement> single;
  glm::vec3 extent{0.0f};
  glm::vec3 used{0.0f};
  float largest = 0.0f;
};
GridFitStart start_grid_fit(const Bounds& bounds);

// `params` (any field's parameters) moved onto `grid`.
template <typename Params>
Params placed(Params params, const GridPlacement& grid) {
  params.origin = grid.origin;
  params.spacing = grid.spacing;
  params.counts = grid.counts;
  return params;
}

// The grid's entries of a field's parameter table (`Params` has origin, spacing and counts).
template <typename Params>
std::vector<ParamSpec<Params>> grid_params(int max_count_per_axis, uint64_t max_probes) {
  return {
      param::vec3("origin", &Params::origin, param::VectorRange::kFinite,
                  "world position of probe (0,0,0)"),
      param::vec3("spacing", &Params::spacing, param::VectorRange::kPositive,
                  "distance between probes per axis"),
      param::probe_counts("counts", &Params::counts, 1, max_count_per_axis, max_probes,
                          "probes per axis"),
  };
}

}  // namespace ddgi
