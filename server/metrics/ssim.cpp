#include "metrics/ssim.h"

#include <string>

#include "metrics/filter.h"

namespace ddgi::metrics {

namespace {

Plane luma(const RgbImageView& image) {
  Plane out(image.width, image.height);
  for (size_t i = 0; i < out.values.size(); ++i) {
    out.values[i] =
        0.2126 * image.rgb[i * 3] + 0.7152 * image.rgb[i * 3 + 1] + 0.0722 * image.rgb[i * 3 + 2];
  }
  return out;
}

Plane product(const Plane& a, const Plane& b) {
  Plane out(a.width, a.height);
  for (size_t i = 0; i < out.values.size(); ++i) out.values[i] = a.values[i] * b.values[i];
  return out;
}

}  // namespace

Result<double> ssim(const RgbImageView& a, const RgbImageView& b, const SsimOptions& options) {
  DDGI_TRY(check_pair(a, b));
  if (options.radius < 0 || !(options.sigma > 0.0) || !(options.dynamic_range > 0.0)) {
    return invalid_argument("SSIM needs radius >= 0, sigma > 0 and dynamic_range > 0");
  }
  const uint32_t window = 2 * static_cast<uint32_t>(options.radius) + 1;
  if (a.width < window || a.height < window) {
    return invalid_argument("SSIM needs images of at least " + std::to_string(window) + "x" +
                            std::to_string(window) + " pixels, got " + std::to_string(a.width) +
                            "x" + std::to_string(a.height));
  }
  const Kernel1D kernel = gaussian_kernel(options.sigma, options.radius);
  const Plane x = luma(a);
  const Plane y = luma(b);
  // Local weighted moments. Away from the border the clamped convolution equals the plain one,
  // and only those positions are averaged below.
  const Plane mean_x = convolve_separable(x, kernel, kernel);
  const Plane mean_y = convolve_separable(y, kernel, kernel);
  const Plane mean_xx = convolve_separable(product(x, x), kernel, kernel);
  const Plane mean_yy = convolve_separable(product(y, y), kernel, kernel);
  const Plane mean_xy = convolve_separable(product(x, y), kernel, kernel);

  const double c1 = (options.k1 * options.dynamic_range) * (options.k1 * options.dynamic_range);
  const double c2 = (options.k2 * options.dynamic_range) * (options.k2 * options.dynamic_range);
  const uint32_t r = static_cast<uint32_t>(options.radius);
  double sum = 0.0;
  for (uint32_t py = r; py < a.height - r; ++py) {
    for (uint32_t px = r; px < a.width - r; ++px) {
      const double mx = mean_x.at(px, py);
      const double my = mean_y.at(px, py);
      const double var_x = mean_xx.at(px, py) - mx * mx;
      const double var_y = mean_yy.at(px, py) - my * my;
      const double cov = mean_xy.at(px, py) - mx * my;
      sum += ((2.0 * mx * my + c1) * (2.0 * cov + c2)) /
             ((mx * mx + my * my + c1) * (var_x + var_y + c2));
    }
  }
  const double count = double(a.width - 2 * r) * double(a.height - 2 * r);
  return sum / count;
}

}  // namespace ddgi::metrics
