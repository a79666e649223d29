#include "metrics/flip_features.h"

#include <cmath>
#include <utility>
#include <vector>

namespace ddgi::metrics {

namespace {

constexpr double kFeatureWidthDegrees = 0.082;

double feature_sigma(double ppd) {
  return 0.5 * kFeatureWidthDegrees * ppd;
}

Kernel1D balanced(std::vector<double> taps) {
  double positive = 0.0;
  double negative = 0.0;
  for (double tap : taps) (tap > 0.0 ? positive : negative) += tap;
  for (double& tap : taps) tap = tap > 0.0 ? tap / positive : tap / -negative;
  return Kernel1D{std::move(taps)};
}

struct FeatureKernels {
  Kernel1D smooth;  // Gaussian across the derivative direction
  Kernel1D edge;    // first derivative
  Kernel1D point;   // second derivative
};

FeatureKernels feature_kernels(double ppd) {
  const double sigma = feature_sigma(ppd);
  const int radius = feature_radius(ppd);
  std::vector<double> edge;
  std::vector<double> point;
  for (int k = -radius; k <= radius; ++k) {
    const double g = std::exp(-(k * k) / (2.0 * sigma * sigma));
    edge.push_back(-k / (sigma * sigma) * g);
    point.push_back((k * k / (sigma * sigma) - 1.0) / (sigma * sigma) * g);
  }
  return {gaussian_kernel(sigma, radius), balanced(std::move(edge)), balanced(std::move(point))};
}

}  // namespace

int feature_radius(double ppd) {
  return static_cast<int>(std::ceil(3.0 * feature_sigma(ppd)));
}

Features detect_features(const Plane& luminance, double ppd) {
  const FeatureKernels kernels = feature_kernels(ppd);
  const Plane edge_x = convolve_separable(luminance, kernels.edge, kernels.smooth);
  const Plane edge_y = convolve_separable(luminance, kernels.smooth, kernels.edge);
  const Plane point_x = convolve_separable(luminance, kernels.point, kernels.smooth);
  const Plane point_y = convolve_separable(luminance, kernels.smooth, kernels.point);
  Features out{Plane(luminance.width, luminance.height), Plane(luminance.width, luminance.height)};
  for (size_t i = 0; i < luminance.values.size(); ++i) {
    out.edges.values[i] = std::hypot(edge_x.values[i], edge_y.values[i]);
    out.points.values[i] = std::hypot(point_x.values[i], point_y.values[i]);
  }
  return out;
}

}  // namespace ddgi::metrics
