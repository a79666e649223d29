// Separable convolution for SSIM and FLIP, rows split over the metrics pool (metrics/parallel.h).
#include "metrics/filter.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "metrics/parallel.h"

namespace ddgi::metrics {

Kernel1D gaussian_kernel(double sigma, int radius) {
  Kernel1D kernel;
  kernel.taps.resize(size_t(2 * radius + 1));
  double sum = 0.0;
  for (int i = -radius; i <= radius; ++i) sum += std::exp(-(i * i) / (2.0 * sigma * sigma));
  for (int i = -radius; i <= radius; ++i) {
    kernel.taps[size_t(i + radius)] = std::exp(-(i * i) / (2.0 * sigma * sigma)) / sum;
  }
  return kernel;
}

namespace {

int clamp_index(int i, uint32_t size) {
  return std::clamp(i, 0, static_cast<int>(size) - 1);
}

// Runs row(y) for every y < height, in bands of rows spread over the metrics pool.
void for_each_row(uint32_t height, const std::function<void(uint32_t)>& row) {
  constexpr size_t kRowsPerBand = 16;  // enough work per band to hide the pool's hand-off
  for_each_chunk(height, kRowsPerBand, [&](size_t begin, size_t end) {
    for (size_t y = begin; y < end; ++y) row(static_cast<uint32_t>(y));
  });
}

}  // namespace

Plane convolve_separable(const Plane& input, const Kernel1D& horizontal, const Kernel1D& vertical) {
  const uint32_t width = input.width;
  const uint32_t height = input.height;
  Plane rows(width, height);
  const int rh = horizontal.radius();
  for_each_row(height, [&](uint32_t y) {
    for (uint32_t x = 0; x < width; ++x) {
      double sum = 0.0;
      for (int k = -rh; k <= rh; ++k) {
        const int sx = clamp_index(static_cast<int>(x) + k, width);
        sum += horizontal.taps[size_t(k + rh)] * input.at(uint32_t(sx), y);
      }
      rows.at(x, y) = sum;
    }
  });
  Plane out(width, height);
  const int rv = vertical.radius();
  for_each_row(height, [&](uint32_t y) {
    for (uint32_t x = 0; x < width; ++x) {
      double sum = 0.0;
      for (int k = -rv; k <= rv; ++k) {
        const int sy = clamp_index(static_cast<int>(y) + k, height);
        sum += vertical.taps[size_t(k + rv)] * rows.at(x, uint32_t(sy));
      }
      out.at(x, y) = sum;
    }
  });
  return out;
}

}  // namespace ddgi::metrics
