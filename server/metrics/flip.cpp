#include "metrics/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "metrics/color.h"
#include "metrics/filter.h"

namespace ddgi::metrics {

namespace {

// Constants from the paper. Colour pipeline: the colour difference is raised to q_c, then
// re-mapped piecewise-linearly so that the p_c fraction of the largest difference maps to p_t.
constexpr double kQc = 0.7;
constexpr double kPc = 0.4;
constexpr double kPt = 0.95;
// Feature pipeline: exponent on the feature difference, and the feature width in degrees.
constexpr double kQf = 0.5;
constexpr double kFeatureWidthDegrees = 0.082;

// Contrast sensitivity per opponent channel, a sum of two Gaussians in the spatial domain:
// S(r) = a1 sqrt(pi/b1) exp(-pi^2 r^2/b1) + a2 sqrt(pi/b2) exp(-pi^2 r^2/b2), r in degrees.
struct Csf {
  double a1, b1, a2, b2;
};
constexpr std::array<Csf, 3> kCsf = {{
    {1.0, 0.0047, 0.0, 1e-5},   // achromatic (Y)
    {1.0, 0.0053, 0.0, 1e-5},   // red-green (Cx)
    {34.1, 0.04, 13.5, 0.025},  // blue-yellow (Cz)
}};
constexpr double kWidestB = 0.04;

// The three YCxCz planes of an image.
struct Opponent {
  std::array<Plane, 3> channels;
};

Opponent to_opponent(const RgbImageView& image) {
  Opponent out;
  for (Plane& plane : out.channels) plane = Plane(image.width, image.height);
  const size_t count = size_t{image.width} * image.height;
  for (size_t i = 0; i < count; ++i) {
    Color3 rgb;
    double* dst[3] = {&rgb.c0, &rgb.c1, &rgb.c2};
    for (size_t c = 0; c < 3; ++c) {
      *dst[c] = srgb_to_linear(std::clamp(double{image.rgb[i * 3 + c]}, 0.0, 1.0));
    }
    const Color3 ycxcz = xyz_to_ycxcz(linear_rgb_to_xyz(rgb));
    out.channels[0].values[i] = ycxcz.c0;
    out.channels[1].values[i] = ycxcz.c1;
    out.channels[2].values[i] = ycxcz.c2;
  }
  return out;
}

// One Gaussian term of a CSF, sampled at whole-pixel offsets converted to degrees.
struct CsfTerm {
  Kernel1D kernel;  // normalised to sum 1
  double weight;    // this term's share of the normalised 2-D kernel
};

std::vector<CsfTerm> csf_terms(const Csf& csf, double ppd) {
  const int radius = static_cast<int>(
      std::ceil(3.0 * std::sqrt(kWidestB / (2.0 * std::numbers::pi * std::numbers::pi)) * ppd));
  std::vector<CsfTerm> terms;
  double total = 0.0;
  for (auto [a, b] : {std::pair{csf.a1, csf.b1}, std::pair{csf.a2, csf.b2}}) {
    if (a == 0.0) continue;
    CsfTerm term;
    term.kernel.taps.resize(size_t(2 * radius + 1));
    double sum = 0.0;
    for (int k = -radius; k <= radius; ++k) {
      const double degrees = k / ppd;
      const double tap = std::exp(-std::numbers::pi * std::numbers::pi * degrees * degrees / b);
      term.kernel.taps[size_t(k + radius)] = tap;
      sum += tap;
    }
    for (double& tap : term.kernel.taps) tap /= sum;
    // The 2-D kernel of this term is separable, g(x) g(y), and sums to amplitude * sum^2.
    term.weight = a * std::sqrt(std::numbers::pi / b) * sum * sum;
    total += term.weight;
    terms.push_back(std::move(term));
  }
  for (CsfTerm& term : terms) term.weight /= total;
  return terms;
}

Plane csf_filter(const Plane& input, const Csf& csf, double ppd) {
  Plane out(input.width, input.height);
  for (const CsfTerm& term : csf_terms(csf, ppd)) {
    const Plane filtered = convolve_separable(input, term.kernel, term.kernel);
    for (size_t i = 0; i < out.values.size(); ++i)
      out.values[i] += term.weight * filtered.values[i];
  }
  return out;
}

// Filtered YCxCz -> linear RGB clamped to the display gamut -> Hunt-adjusted L*a*b*.
std::vector<Color3> to_hunt_lab(const Opponent& filtered) {
  const size_t count = filtered.channels[0].values.size();
  std::vector<Color3> out(count);
  for (size_t i = 0; i < count; ++i) {
    const Color3 ycxcz{filtered.channels[0].values[i], filtered.channels[1].values[i],
                       filtered.channels[2].values[i]};
    Color3 rgb = xyz_to_linear_rgb(ycxcz_to_xyz(ycxcz));
    rgb = {std::clamp(rgb.c0, 0.0, 1.0), std::clamp(rgb.c1, 0.0, 1.0),
           std::clamp(rgb.c2, 0.0, 1.0)};
    out[i] = hunt_adjust(xyz_to_lab(linear_rgb_to_xyz(rgb)));
  }
  return out;
}

Color3 hunt_lab_of_linear(const Color3& rgb) {
  return hunt_adjust(xyz_to_lab(linear_rgb_to_xyz(rgb)));
}

// The largest colour difference the re-mapping is scaled to: pure green vs pure blue, which the
// paper takes as the most different pair of display colours under HyAB with the Hunt effect.
double max_color_difference() {
  return std::pow(hyab(hunt_lab_of_linear({0.0, 1.0, 0.0}), hunt_lab_of_linear({0.0, 0.0, 1.0})),
                  kQc);
}

// HyAB^q_c compressed into [0,1]: linear up to p_c * cmax (reaching p_t there), then a gentle
// linear ramp over the remaining range so large differences stay distinguishable.
double remap_color_difference(double distance, double cmax) {
  const double d = std::pow(distance, kQc);
  const double knee = kPc * cmax;
  const double mapped =
      d < knee ? (kPt / knee) * d : kPt + (d - knee) / (cmax - knee) * (1.0 - kPt);
  return std::clamp(mapped, 0.0, 1.0);
}

// First and second derivative-of-Gaussian taps, scaled so the positive taps sum to 1 and the
// negative taps to -1: the response to a constant is 0 and to a full-range step or dot is 1.
Kernel1D balanced(std::vector<double> taps) {
  double positive = 0.0;
  double negative = 0.0;
  for (double tap : taps) (tap > 0.0 ? positive : negative) += tap;
  for (double& tap : taps) tap = tap > 0.0 ? tap / positive : tap / -negative;
  return Kernel1D{std::move(taps)};
}

struct FeatureKernels {
  Kernel1D smooth;  // Gaussian across the derivative direction
  Kernel1D edge;    // first derivative (edges)
  Kernel1D point;   // second derivative (points)
};

FeatureKernels feature_kernels(double ppd) {
  const double sigma = 0.5 * kFeatureWidthDegrees * ppd;
  const int radius = static_cast<int>(std::ceil(3.0 * sigma));
  std::vector<double> edge;
  std::vector<double> point;
  for (int k = -radius; k <= radius; ++k) {
    const double g = std::exp(-(k * k) / (2.0 * sigma * sigma));
    edge.push_back(-k / (sigma * sigma) * g);
    point.push_back((k * k / (sigma * sigma) - 1.0) / (sigma * sigma) * g);
  }
  return {gaussian_kernel(sigma, radius), balanced(std::move(edge)), balanced(std::move(point))};
}

struct Features {
  Plane edges;   // gradient magnitude of the edge filter pair
  Plane points;  // magnitude of the point filter pair
};

// On the normalised achromatic channel Y/Yn = (Y + 16) / 116 of the unfiltered image, in [0,1].
Features detect_features(const Plane& achromatic, const FeatureKernels& kernels) {
  Plane luminance(achromatic.width, achromatic.height);
  for (size_t i = 0; i < luminance.values.size(); ++i) {
    luminance.values[i] = (achromatic.values[i] + 16.0) / 116.0;
  }
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

}  // namespace

double pixels_per_degree(double distance_m, double resolution_x, double monitor_width_m) {
  return distance_m * (resolution_x / monitor_width_m) * (std::numbers::pi / 180.0);
}

Result<FlipResult> flip(const RgbImageView& reference, const RgbImageView& test,
                        const FlipOptions& options) {
  DDGI_TRY(check_pair(reference, test));
  const double ppd = options.pixels_per_degree;
  if (!(ppd > 0.0 && ppd <= 1000.0)) {
    return invalid_argument("FLIP pixels per degree must be in (0, 1000], got " +
                            std::to_string(ppd));
  }
  const Opponent ref_opponent = to_opponent(reference);
  const Opponent test_opponent = to_opponent(test);

  // Colour pipeline: what survives the eye's contrast sensitivity, compared in a perceptual space.
  Opponent ref_filtered;
  Opponent test_filtered;
  for (size_t c = 0; c < 3; ++c) {
    ref_filtered.channels[c] = csf_filter(ref_opponent.channels[c], kCsf[c], ppd);
    test_filtered.channels[c] = csf_filter(test_opponent.channels[c], kCsf[c], ppd);
  }
  const std::vector<Color3> ref_lab = to_hunt_lab(ref_filtered);
  const std::vector<Color3> test_lab = to_hunt_lab(test_filtered);

  // Feature pipeline: edges and points that appear, vanish or change in strength.
  const FeatureKernels kernels = feature_kernels(ppd);
  const Features ref_features = detect_features(ref_opponent.channels[0], kernels);
  const Features test_features = detect_features(test_opponent.channels[0], kernels);

  const double cmax = max_color_difference();
  FlipResult result{reference.width, reference.height, {}, 0.0};
  result.error_map.resize(ref_lab.size());
  double sum = 0.0;
  for (size_t i = 0; i < ref_lab.size(); ++i) {
    const double color = remap_color_difference(hyab(ref_lab[i], test_lab[i]), cmax);
    const double edge_diff = std::abs(ref_features.edges.values[i] - test_features.edges.values[i]);
    const double point_diff =
        std::abs(ref_features.points.values[i] - test_features.points.values[i]);
    const double feature =
        std::min(1.0, std::pow(std::max(edge_diff, point_diff) / std::numbers::sqrt2, kQf));
    // Feature differences amplify the colour error: the exponent shrinks towards 0.
    const double error = std::pow(color, 1.0 - feature);
    result.error_map[i] = static_cast<float>(error);
    sum += error;
  }
  result.mean = sum / static_cast<double>(ref_lab.size());
  return result;
}

}  // namespace ddgi::metrics
