// Structural similarity (Wang, Bovik, Sheikh, Simoncelli, "Image Quality Assessment: From Error
// Visibility to Structural Similarity", IEEE TIP 2004).
#pragma once

#include "core/result.h"
#include "metrics/image_view.h"

namespace ddgi::metrics {

struct SsimOptions {
  double dynamic_range = 1.0;  // L in C1 = (K1 L)^2, C2 = (K2 L)^2: 1 for values in [0,1]
  double k1 = 0.01;            // Wang et al.'s constant keeping the luminance term stable near 0
  double k2 = 0.03;            // Wang et al.'s constant for the contrast-structure term
  double sigma = 1.5;          // Gaussian window standard deviation in pixels, as in the paper
  int radius = 5;              // window of 2*5+1 = 11 pixels per side, as in the paper
};

// Mean SSIM over all window positions that fit entirely inside the image (the "valid" region,
// as in Wang's reference MATLAB code, without its automatic downsampling). Computed on one
// channel, the luma Y = 0.2126 R + 0.7152 G + 0.0722 B of the values as given (so for
// display-encoded images this is luma of the encoded values, the usual convention). Images
// must be at least (2*radius+1) pixels on each side. Identical images give exactly 1; the
// result lies in [-1, 1] and is symmetric in a and b.
Result<double> ssim(const RgbImageView& a, const RgbImageView& b, const SsimOptions& options = {});

}  // namespace ddgi::metrics
