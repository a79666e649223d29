// Single-channel planes and separable convolution, shared by SSIM and FLIP.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ddgi::metrics {

struct Plane {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<double> values;  // row-major; double so SSIM's E[x^2]-E[x]^2 keeps its digits

  Plane() = default;
  Plane(uint32_t w, uint32_t h) : width(w), height(h), values(size_t{w} * h, 0.0) {}
  double& at(uint32_t x, uint32_t y) { return values[size_t{y} * width + x]; }
  double at(uint32_t x, uint32_t y) const { return values[size_t{y} * width + x]; }
};

// A 1-D kernel of odd length 2r+1; taps[r] is the centre (derivative kernels are odd).
struct Kernel1D {
  std::vector<double> taps;
  int radius() const { return static_cast<int>(taps.size() / 2); }
};

// Samples exp(-x^2 / (2 sigma^2)) for |x| <= radius, normalised to sum 1.
Kernel1D gaussian_kernel(double sigma, int radius);

// Convolves rows with `horizontal`, then columns with `vertical`. Pixels outside the image
// repeat the nearest edge pixel (clamp-to-edge), so a constant image stays constant under any
// kernel that sums to 1.
Plane convolve_separable(const Plane& input, const Kernel1D& horizontal, const Kernel1D& vertical);

}  // namespace ddgi::metrics
