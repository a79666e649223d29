#include <cmath>

#include <gtest/gtest.h>

#include "metrics/ssim.h"
#include "test_images.h"

namespace ddgi::metrics {
namespace {

using test::constant_image;
using test::TestImage;

constexpr double kC1 = 0.01 * 0.01;
constexpr double kC2 = 0.03 * 0.03;

// Grey image whose value rises linearly along x: v = slope * x + offset.
TestImage ramp(uint32_t width, uint32_t height, double slope, double offset) {
  TestImage image = constant_image(width, height, 0.0f, 0.0f, 0.0f);
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const float v = float(slope * x + offset);
      for (uint32_t c = 0; c < 3; ++c) image.at(x, y, c) = v;
    }
  }
  return image;
}

TEST(Ssim, IdenticalImagesGiveExactlyOne) {
  const TestImage a = test::add_noise(test::gradient_image(40, 30), 0.2f);
  EXPECT_EQ(*ssim(a.view(), a.view()), 1.0);
}

TEST(Ssim, BrightnessShiftOfFlatImagesMatchesTheLuminanceTerm) {
  // No variance anywhere, so the contrast-structure term is C2/C2 = 1 and SSIM reduces to
  // (2ab + C1) / (a^2 + b^2 + C1).
  const double a = 0.5;
  const double b = 0.6;
  const TestImage x = constant_image(16, 16, float(a), float(a), float(a));
  const TestImage y = constant_image(16, 16, float(b), float(b), float(b));
  const double expected = (2.0 * double(float(a)) * double(float(b)) + kC1) /
                          (double(float(a)) * float(a) + double(float(b)) * float(b) + kC1);
  EXPECT_NEAR(*ssim(x.view(), y.view()), expected, 1e-12);
  EXPECT_NEAR(expected, 0.98361, 1e-5);  // 0.61 / 0.6101 worked by hand
}

TEST(Ssim, ContrastChangeOfARampMatchesTheClosedForm) {
  // x = s*i + t along each row; y = k*x + c. Under a normalised symmetric window every position
  // sees mean(x) = x(centre) and var(x) = s^2 V, with V the window's second moment in pixels^2;
  // cov(x, y) = k s^2 V and var(y) = k^2 s^2 V. So each window's SSIM is known in closed form.
  const uint32_t width = 18;
  const uint32_t height = 12;
  const double s = 0.04;
  const double t = 0.1;
  const double k = 0.5;
  const double c = 0.2;
  const TestImage x = ramp(width, height, s, t);
  const TestImage y = ramp(width, height, k * s, k * t + c);

  double weight_sum = 0.0;
  double second_moment = 0.0;
  for (int i = -5; i <= 5; ++i) {
    const double w = std::exp(-(i * i) / (2.0 * 1.5 * 1.5));
    weight_sum += w;
    second_moment += w * i * i;
  }
  const double variance_x = s * s * second_moment / weight_sum;
  double sum = 0.0;
  int windows = 0;
  for (uint32_t cy = 5; cy < height - 5; ++cy) {
    for (uint32_t cx = 5; cx < width - 5; ++cx) {
      const double mx = s * cx + t;
      const double my = k * mx + c;
      sum += ((2 * mx * my + kC1) * (2 * k * variance_x + kC2)) /
             ((mx * mx + my * my + kC1) * ((1 + k * k) * variance_x + kC2));
      ++windows;
    }
  }
  // Inputs are stored as float, hence a float-sized tolerance.
  EXPECT_NEAR(*ssim(x.view(), y.view()), sum / windows, 1e-6);
}

TEST(Ssim, InvertedStructureIsNegative) {
  const TestImage x = ramp(20, 12, 0.04, 0.1);
  const TestImage y = ramp(20, 12, -0.04, 0.9);
  EXPECT_LT(*ssim(x.view(), y.view()), 0.0);
}

TEST(Ssim, SymmetricBoundedAndDecreasingWithNoise) {
  const TestImage base = test::gradient_image(48, 32);
  double previous = 1.0;
  for (float amplitude : {0.01f, 0.03f, 0.1f, 0.3f}) {
    const TestImage noisy = test::add_noise(base, amplitude);
    const double forward = *ssim(base.view(), noisy.view());
    EXPECT_EQ(forward, *ssim(noisy.view(), base.view()));
    EXPECT_GE(forward, -1.0);
    EXPECT_LT(forward, previous) << amplitude;
    previous = forward;
  }
}

TEST(Ssim, RejectsTooSmallAndMismatchedImages) {
  const TestImage small = constant_image(10, 20, 0.5f, 0.5f, 0.5f);
  Result<double> result = ssim(small.view(), small.view());
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("11x11"), std::string::npos);
  const TestImage a = constant_image(12, 12, 0.5f, 0.5f, 0.5f);
  const TestImage b = constant_image(13, 12, 0.5f, 0.5f, 0.5f);
  Result<double> mismatch = ssim(a.view(), b.view());
  ASSERT_FALSE(mismatch.ok());
  EXPECT_NE(mismatch.error().message.find("12x12 vs 13x12"), std::string::npos);
}

}  // namespace
}  // namespace ddgi::metrics
