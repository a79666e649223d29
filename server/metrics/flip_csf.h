// FLIP's spatial filtering: the contrast sensitivity of the eye per opponent channel, as
// spatial-domain kernels for a given viewing condition (pixels per degree).
#pragma once

#include "metrics/filter.h"

namespace ddgi::metrics {

enum class OpponentChannel { kAchromatic = 0, kRedGreen = 1, kBlueYellow = 2 };

// Kernel radius in pixels, shared by all channels: three standard deviations of the widest
// Gaussian (blue-yellow, b = 0.04) at this ppd; 10 pixels at 67 ppd.
int csf_radius(double ppd);

// Convolves a YCxCz plane with its channel's normalised CSF kernel (clamp-to-edge borders).
Plane csf_filter(const Plane& input, OpponentChannel channel, double ppd);

}  // namespace ddgi::metrics
