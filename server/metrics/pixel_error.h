// Per-pixel error statistics: RMSE and PSNR. Any value range; PSNR needs to be told the peak.
#pragma once

#include "core/result.h"
#include "metrics/image_view.h"

namespace ddgi::metrics {

// sqrt(mean of squared differences) over every channel of every pixel, in the images' units.
Result<double> rmse(const RgbImageView& a, const RgbImageView& b);

// 20 * log10(peak / RMSE) in dB. `peak` is the nominal maximum of the value range: 1.0 for
// images in [0,1] (what ddgi-compare passes), 255 for 8-bit codes. Identical images give
// +infinity. The images are usually display-encoded (sRGB); PSNR on linear HDR data is only
// meaningful with a stated peak.
Result<double> psnr(const RgbImageView& a, const RgbImageView& b, double peak = 1.0);

}  // namespace ddgi::metrics
