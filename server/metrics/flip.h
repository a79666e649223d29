// LDR-FLIP: Andersson, Nilsson, Akenine-Moller, Oskarsson, Astrom, Fairchild, "FLIP: A
// Difference Evaluator for Alternating Images", Proc. ACM Comput. Graph. Interact. Tech. (HPG)
// 2020. Predicts what an observer flipping between two images at a given viewing distance would
// notice, per pixel. Implemented from the paper's description (see docs/metrics.md for the
// choices the paper leaves open).
#pragma once

#include <cstdint>
#include <vector>

#include "core/result.h"
#include "metrics/image_view.h"

namespace ddgi::metrics {

// Pixels per degree of visual angle for a viewer `distance_m` from a monitor `monitor_width_m`
// wide showing `resolution_x` pixels across.
double pixels_per_degree(double distance_m, double resolution_x, double monitor_width_m);

struct FlipOptions {
  // The paper's default viewer: 0.7 m from a 0.7 m wide, 3840-pixel monitor (67.02 ppd).
  // Larger values mean a more distant viewer, who sees fewer fine differences.
  double pixels_per_degree = 67.0;
};

struct FlipResult {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<float> error_map;  // per-pixel error in [0,1], row-major, top row first
  double mean = 0.0;             // mean of error_map, FLIP's usual one-number summary
};

// Inputs are sRGB-encoded (display) LDR images with values in [0,1]; values outside are clamped
// (HDR images must be exposed and tone-mapped first). Sizes must match. Identical images give
// exactly 0 everywhere; the result is symmetric in its two arguments. pixels_per_degree must be
// in (0, 1000].
Result<FlipResult> flip(const RgbImageView& reference, const RgbImageView& test,
                        const FlipOptions& options = {});

}  // namespace ddgi::metrics
