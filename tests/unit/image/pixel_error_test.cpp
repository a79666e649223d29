#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "metrics/pixel_error.h"
#include "test_images.h"

namespace ddgi::metrics {
namespace {

using test::constant_image;
using test::TestImage;

TEST(Rmse, ConstantOffsetIsTheOffset) {
  // 0.25 and 0.375 are exact in binary, so every step of the computation is exact.
  const TestImage a = constant_image(16, 9, 0.25f, 0.25f, 0.25f);
  const TestImage b = constant_image(16, 9, 0.375f, 0.375f, 0.375f);
  EXPECT_EQ(*rmse(a.view(), b.view()), 0.125);
  EXPECT_EQ(*rmse(b.view(), a.view()), 0.125);
}

TEST(Rmse, SingleChannelDifferenceAveragesOverAllChannels) {
  TestImage a = constant_image(2, 2, 0.0f, 0.0f, 0.0f);
  TestImage b = a;
  b.at(1, 1, 2) = 0.5f;  // one value of twelve differs by 0.5
  EXPECT_DOUBLE_EQ(*rmse(a.view(), b.view()), std::sqrt(0.25 / 12.0));
}

TEST(Psnr, ConstantOffsetMatchesTheFormula) {
  const TestImage a = constant_image(16, 9, 0.25f, 0.25f, 0.25f);
  const TestImage b = constant_image(16, 9, 0.375f, 0.375f, 0.375f);
  EXPECT_DOUBLE_EQ(*psnr(a.view(), b.view()), 20.0 * std::log10(1.0 / 0.125));
  EXPECT_NEAR(*psnr(a.view(), b.view()), 18.061799739838872, 1e-12);
  // 8-bit codes with peak 255: offset of 4 codes.
  const TestImage c = constant_image(4, 4, 100.0f, 50.0f, 200.0f);
  const TestImage d = constant_image(4, 4, 104.0f, 54.0f, 204.0f);
  EXPECT_DOUBLE_EQ(*psnr(c.view(), d.view(), 255.0), 20.0 * std::log10(255.0 / 4.0));
}

TEST(Psnr, IdenticalImagesAreInfinite) {
  const TestImage a = test::gradient_image(20, 10);
  EXPECT_EQ(*rmse(a.view(), a.view()), 0.0);
  EXPECT_EQ(*psnr(a.view(), a.view()), std::numeric_limits<double>::infinity());
}

TEST(Psnr, RejectsBadPeak) {
  const TestImage a = constant_image(2, 2, 0.5f, 0.5f, 0.5f);
  EXPECT_FALSE(psnr(a.view(), a.view(), 0.0).ok());
  EXPECT_FALSE(psnr(a.view(), a.view(), -1.0).ok());
}

TEST(PixelError, SizeMismatchNamesBothSizes) {
  const TestImage a = constant_image(64, 48, 0.5f, 0.5f, 0.5f);
  const TestImage b = constant_image(32, 32, 0.5f, 0.5f, 0.5f);
  Result<double> result = rmse(a.view(), b.view());
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(result.error().message.find("64x48"), std::string::npos) << result.error().message;
  EXPECT_NE(result.error().message.find("32x32"), std::string::npos) << result.error().message;
  EXPECT_FALSE(psnr(a.view(), b.view()).ok());
}

TEST(PixelError, RejectsNonFiniteAndShortBuffers) {
  const TestImage a = constant_image(4, 4, 0.5f, 0.5f, 0.5f);
  TestImage nan = a;
  nan.at(2, 3, 1) = std::numeric_limits<float>::quiet_NaN();
  Result<double> result = rmse(a.view(), nan.view());
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("(2, 3)"), std::string::npos) << result.error().message;
  const RgbImageView short_view{4, 4, std::span<const float>(a.rgb).first(10)};
  EXPECT_FALSE(rmse(a.view(), short_view).ok());
}

}  // namespace
}  // namespace ddgi::metrics
