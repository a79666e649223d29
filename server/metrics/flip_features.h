// FLIP's feature detection: edges (first derivative of a Gaussian) and points (second
// derivative) on the achromatic channel, whose appearance or disappearance the eye notices
// more than the colour difference alone suggests.
#pragma once

#include "metrics/filter.h"

namespace ddgi::metrics {

struct Features {
  Plane edges;   // |(edge_x, edge_y)|, in [0, sqrt(2)] for inputs in [0,1]
  Plane points;  // |(point_x, point_y)|, in [0, sqrt(2)] for inputs in [0,1]
};

// Filter standard deviation 0.5 * 0.082 degrees * ppd (the paper's feature width w = 0.082),
// radius ceil(3 sigma): 2.75 and 9 pixels at 67 ppd.
int feature_radius(double ppd);

// `luminance` is the normalised achromatic channel Y/Yn in [0,1] of the unfiltered image. The
// derivative kernels are scaled so their positive taps sum to 1 and their negative taps to -1:
// a constant gives 0 and a full 0 -> 1 step gives an edge response of exactly 1 beside it.
Features detect_features(const Plane& luminance, double ppd);

}  // namespace ddgi::metrics
