// FLIP's two filter stages checked on their own against closed-form answers, so a wrong kernel
// width or a broken feature detector cannot hide behind the end-to-end invariants.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "metrics/flip_csf.h"
#include "metrics/flip_features.h"

namespace ddgi::metrics {
namespace {

constexpr double kPi = std::numbers::pi;

Plane impulse(uint32_t size) {
  Plane plane(size, size);
  plane.at(size / 2, size / 2) = 1.0;
  return plane;
}

double total(const Plane& plane) {
  double sum = 0.0;
  for (double v : plane.values) sum += v;
  return sum;
}

// Variance along x of a plane read as a distribution centred in the plane.
double variance_x(const Plane& plane) {
  const double centre = plane.width / 2;
  double sum = 0.0;
  for (uint32_t y = 0; y < plane.height; ++y) {
    for (uint32_t x = 0; x < plane.width; ++x) sum += plane.at(x, y) * (x - centre) * (x - centre);
  }
  return sum / total(plane);
}

// A Gaussian exp(-pi^2 r^2 / b) in degrees has variance b / (2 pi^2) degrees^2.
double csf_variance_pixels(double b, double ppd) {
  return b / (2.0 * kPi * kPi) * ppd * ppd;
}

TEST(FlipCsf, RadiusFollowsTheWidestGaussian) {
  EXPECT_EQ(csf_radius(67.0), 10);  // 3 * 0.04502 deg * 67 = 9.05 -> 10
  EXPECT_EQ(csf_radius(20.0), 3);
}

TEST(FlipCsf, ImpulseResponsesHaveThePapersWidthsAndUnitSum) {
  const double ppd = 67.0;
  const Plane achromatic = csf_filter(impulse(41), OpponentChannel::kAchromatic, ppd);
  const Plane red_green = csf_filter(impulse(41), OpponentChannel::kRedGreen, ppd);
  const Plane blue_yellow = csf_filter(impulse(41), OpponentChannel::kBlueYellow, ppd);
  for (const Plane* plane : {&achromatic, &red_green, &blue_yellow}) {
    EXPECT_NEAR(total(*plane), 1.0, 1e-12);
  }
  // The narrow Gaussians (sigma ~1 pixel) are 10 sigma wide, so sampling and truncation change
  // their variance by far less than 1e-6.
  EXPECT_NEAR(variance_x(achromatic) / csf_variance_pixels(0.0047, ppd), 1.0, 1e-6);
  EXPECT_NEAR(variance_x(red_green) / csf_variance_pixels(0.0053, ppd), 1.0, 1e-6);
  // Blue-yellow mixes two Gaussians. Continuous weights: a * sqrt(pi/b) times the integral
  // ppd^2 b / pi of the 2-D Gaussian, i.e. proportional to a sqrt(b). The truncation at 3.3 sigma
  // of the wider one lowers the variance by about 1%, hence the 3% tolerance.
  const double w1 = 34.1 * std::sqrt(0.04);
  const double w2 = 13.5 * std::sqrt(0.025);
  const double mixed =
      (w1 * csf_variance_pixels(0.04, ppd) + w2 * csf_variance_pixels(0.025, ppd)) / (w1 + w2);
  EXPECT_NEAR(variance_x(blue_yellow) / mixed, 1.0, 0.03);
  EXPECT_LT(variance_x(blue_yellow), mixed);
}

TEST(FlipCsf, ConstantPlanesStayConstant) {
  Plane flat(23, 17);
  for (double& v : flat.values) v = 42.5;
  for (auto channel : {OpponentChannel::kAchromatic, OpponentChannel::kBlueYellow}) {
    for (double v : csf_filter(flat, channel, 67.0).values) ASSERT_NEAR(v, 42.5, 1e-12);
  }
}

TEST(FlipFeatures, RadiusFollowsTheFeatureWidth) {
  EXPECT_EQ(feature_radius(67.0), 9);  // sigma = 0.041 * 67 = 2.747 pixels
}

TEST(FlipFeatures, FullStepGivesAnEdgeOfExactlyOneBesideIt) {
  // 0 for x < 20, 1 from x = 20: the pixels either side of the step see all positive (or all
  // negative) taps on one side, so the balanced kernel answers exactly 1; pixels more than the
  // 9-pixel radius away see a constant and answer 0.
  Plane step(40, 24);
  for (uint32_t y = 0; y < 24; ++y) {
    for (uint32_t x = 20; x < 40; ++x) step.at(x, y) = 1.0;
  }
  const Features features = detect_features(step, 67.0);
  for (uint32_t y = 0; y < 24; ++y) {
    ASSERT_NEAR(features.edges.at(19, y), 1.0, 1e-12);
    ASSERT_NEAR(features.edges.at(20, y), 1.0, 1e-12);
    ASSERT_NEAR(features.edges.at(10, y), 0.0, 1e-12);
    ASSERT_NEAR(features.edges.at(29, y), 0.0, 1e-12);
    ASSERT_GT(features.edges.at(15, y), 0.1);
  }
  // A half-height step answers one half: the detector is linear before the magnitude.
  Plane half = step;
  for (double& v : half.values) v *= 0.5;
  EXPECT_NEAR(detect_features(half, 67.0).edges.at(20, 5), 0.5, 1e-12);
}

TEST(FlipFeatures, HorizontalStepIsSeenByTheOtherAxis) {
  Plane step(24, 40);
  for (uint32_t y = 20; y < 40; ++y) {
    for (uint32_t x = 0; x < 24; ++x) step.at(x, y) = 1.0;
  }
  EXPECT_NEAR(detect_features(step, 67.0).edges.at(7, 20), 1.0, 1e-12);
}

TEST(FlipFeatures, RampHasEdgesButNoPoints) {
  // The point kernel is even and sums to zero, so it cancels any linear function exactly.
  Plane ramp(48, 30);
  for (uint32_t y = 0; y < 30; ++y) {
    for (uint32_t x = 0; x < 48; ++x) ramp.at(x, y) = 0.01 * x + 0.1;
  }
  const Features features = detect_features(ramp, 67.0);
  for (uint32_t x = 10; x < 38; ++x) {
    ASSERT_NEAR(features.points.at(x, 15), 0.0, 1e-12) << x;
    ASSERT_GT(features.edges.at(x, 15), 0.0) << x;
  }
}

TEST(FlipFeatures, ThinLineIsAPointNotAnEdgeAtItsCentre) {
  Plane line(40, 40);
  for (uint32_t y = 0; y < 40; ++y) line.at(20, y) = 1.0;
  const Features features = detect_features(line, 67.0);
  EXPECT_NEAR(features.edges.at(20, 20), 0.0, 1e-12);  // odd kernel, symmetric input
  EXPECT_GT(features.points.at(20, 20), 0.1);
  EXPECT_GT(features.points.at(20, 20), features.points.at(5, 20));
}

}  // namespace
}  // namespace ddgi::metrics
