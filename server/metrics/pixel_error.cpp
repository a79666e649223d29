#include "metrics/pixel_error.h"

#include <cmath>
#include <limits>

namespace ddgi::metrics {

Result<double> rmse(const RgbImageView& a, const RgbImageView& b) {
  DDGI_TRY(check_pair(a, b));
  double sum = 0.0;
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    const double d = double{a.rgb[i]} - double{b.rgb[i]};
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(a.rgb.size()));
}

Result<double> psnr(const RgbImageView& a, const RgbImageView& b, double peak) {
  if (!(peak > 0.0) || !std::isfinite(peak)) {
    return invalid_argument("PSNR peak must be positive and finite, got " + std::to_string(peak));
  }
  DDGI_ASSIGN_OR_RETURN(const double error, rmse(a, b));
  if (error == 0.0) return std::numeric_limits<double>::infinity();
  return 20.0 * std::log10(peak / error);
}

}  // namespace ddgi::metrics
