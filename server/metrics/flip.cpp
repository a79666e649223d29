// LDR-FLIP (Andersson et al. 2020; metrics/flip.h): the colour and feature pipelines of both
// images and their per-pixel combination, the loops on the metrics pool (metrics/parallel.h).
#include "metrics/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "metrics/color.h"
#include "metrics/filter.h"
#include "metrics/flip_csf.h"
#include "metrics/flip_features.h"
#include "metrics/parallel.h"

namespace ddgi::metrics {

namespace {

// The paper's constants. Colour: the HyAB difference is raised to q_c, then re-mapped piecewise
// linearly so that p_c of the largest difference maps to p_t. Features: exponent q_f.
constexpr double kQc = 0.7;
constexpr double kPc = 0.4;
constexpr double kPt = 0.95;
constexpr double kQf = 0.5;

constexpr size_t kPixelsPerChunk = 16384;  // per-pixel loops' share of work per pool task

// The three YCxCz planes of an image.
using Opponent = std::array<Plane, 3>;

Opponent to_opponent(const RgbImageView& image) {
  Opponent out;
  for (Plane& plane : out) plane = Plane(image.width, image.height);
  const size_t count = size_t{image.width} * image.height;
  for_each_chunk(count, kPixelsPerChunk, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const auto linear = [&](size_t c) {
        return srgb_to_linear(std::clamp(double{image.rgb[i * 3 + c]}, 0.0, 1.0));
      };
      const Color3 ycxcz = xyz_to_ycxcz(linear_rgb_to_xyz({linear(0), linear(1), linear(2)}));
      out[0].values[i] = ycxcz.c0;
      out[1].values[i] = ycxcz.c1;
      out[2].values[i] = ycxcz.c2;
    }
  });
  return out;
}

Opponent csf_filter_all(const Opponent& input, double ppd) {
  return {csf_filter(input[0], OpponentChannel::kAchromatic, ppd),
          csf_filter(input[1], OpponentChannel::kRedGreen, ppd),
          csf_filter(input[2], OpponentChannel::kBlueYellow, ppd)};
}

// Filtered YCxCz -> linear RGB clamped to the display gamut -> Hunt-adjusted L*a*b*.
std::vector<Color3> to_hunt_lab(const Opponent& filtered) {
  const size_t count = filtered[0].values.size();
  std::vector<Color3> out(count);
  for_each_chunk(count, kPixelsPerChunk, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const Color3 ycxcz{filtered[0].values[i], filtered[1].values[i], filtered[2].values[i]};
      const Color3 rgb = xyz_to_linear_rgb(ycxcz_to_xyz(ycxcz));
      const Color3 clamped{std::clamp(rgb.c0, 0.0, 1.0), std::clamp(rgb.c1, 0.0, 1.0),
                           std::clamp(rgb.c2, 0.0, 1.0)};
      out[i] = hunt_adjust(xyz_to_lab(linear_rgb_to_xyz(clamped)));
    }
  });
  return out;
}

// Y/Yn = (Y + 16) / 116 of the unfiltered achromatic channel: the feature detectors' input.
Plane normalized_luminance(const Plane& achromatic) {
  Plane out(achromatic.width, achromatic.height);
  for (size_t i = 0; i < out.values.size(); ++i) {
    out.values[i] = (achromatic.values[i] + 16.0) / 116.0;
  }
  return out;
}

Color3 hunt_lab_of_linear(const Color3& rgb) {
  return hunt_adjust(xyz_to_lab(linear_rgb_to_xyz(rgb)));
}

// The largest colour difference the re-mapping is scaled to: pure green vs pure blue, the most
// different pair of display colours under HyAB with the Hunt adjustment.
double max_color_difference() {
  return std::pow(hyab(hunt_lab_of_linear({0.0, 1.0, 0.0}), hunt_lab_of_linear({0.0, 0.0, 1.0})),
                  kQc);
}

// HyAB^q_c compressed into [0,1]: linear up to p_c * cmax (reaching p_t there), then a gentle
// linear ramp over the rest so large differences stay distinguishable.
double remap_color_difference(double distance, double cmax) {
  const double d = std::pow(distance, kQc);
  const double knee = kPc * cmax;
  const double mapped =
      d < knee ? (kPt / knee) * d : kPt + (d - knee) / (cmax - knee) * (1.0 - kPt);
  return std::clamp(mapped, 0.0, 1.0);
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

  // Colour pipeline: what survives the eye's contrast sensitivity, compared perceptually.
  const std::vector<Color3> ref_lab = to_hunt_lab(csf_filter_all(ref_opponent, ppd));
  const std::vector<Color3> test_lab = to_hunt_lab(csf_filter_all(test_opponent, ppd));

  // Feature pipeline: edges and points that appear, vanish or change in strength.
  const Features ref_features = detect_features(normalized_luminance(ref_opponent[0]), ppd);
  const Features test_features = detect_features(normalized_luminance(test_opponent[0]), ppd);

  const double cmax = max_color_difference();
  FlipResult result{reference.width, reference.height, {}, 0.0};
  const size_t count = ref_lab.size();
  result.error_map.resize(count);
  // Per-chunk sums added in chunk order: the mean does not depend on the thread count.
  std::vector<double> chunk_sums((count + kPixelsPerChunk - 1) / kPixelsPerChunk, 0.0);
  for_each_chunk(count, kPixelsPerChunk, [&](size_t begin, size_t end) {
    double sum = 0.0;
    for (size_t i = begin; i < end; ++i) {
      const double color = remap_color_difference(hyab(ref_lab[i], test_lab[i]), cmax);
      const double edge_diff =
          std::abs(ref_features.edges.values[i] - test_features.edges.values[i]);
      const double point_diff =
          std::abs(ref_features.points.values[i] - test_features.points.values[i]);
      const double feature =
          std::min(1.0, std::pow(std::max(edge_diff, point_diff) / std::numbers::sqrt2, kQf));
      // Feature differences amplify the colour error: the exponent shrinks towards 0.
      const double error = std::pow(color, 1.0 - feature);
      result.error_map[i] = static_cast<float>(error);
      sum += error;
    }
    chunk_sums[begin / kPixelsPerChunk] = sum;
  });
  double sum = 0.0;
  for (double chunk_sum : chunk_sums) sum += chunk_sum;
  result.mean = sum / static_cast<double>(count);
  return result;
}

}  // namespace ddgi::metrics
