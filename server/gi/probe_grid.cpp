// Shared probe-grid helpers (probe_grid.h).
#include "gi/probe_grid.h"

#include <algorithm>
#include <cmath>

namespace ddgi {

uint64_t grid_probe_count(glm::ivec3 counts) {
  return uint64_t(std::max(counts.x, 0)) * uint64_t(std::max(counts.y, 0)) *
         uint64_t(std::max(counts.z, 0));
}

SquareTiling square_tiling(uint64_t tiles) {
  SquareTiling tiling;
  tiles = std::max<uint64_t>(tiles, 1);
  tiling.tiles_per_row = static_cast<uint32_t>(std::ceil(std::sqrt(double(tiles))));
  tiling.rows = static_cast<uint32_t>((tiles + tiling.tiles_per_row - 1) / tiling.tiles_per_row);
  return tiling;
}

GridFitStart start_grid_fit(const Bounds& bounds) {
  GridFitStart fit;
  if (bounds.empty()) {
    fit.single = GridPlacement{};
    return fit;
  }
  fit.extent = glm::max(bounds.extent(), glm::vec3(0.0f));
  fit.largest = std::max({fit.extent.x, fit.extent.y, fit.extent.z});
  if (!(fit.largest > 0.0f)) {
    fit.single = GridPlacement{bounds.center(), glm::vec3(1.0f), glm::ivec3(1)};
    return fit;
  }
  fit.used = glm::max(fit.extent, glm::vec3(fit.largest * 0.01f));
  return fit;
}

}  // namespace ddgi
