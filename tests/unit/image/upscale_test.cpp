// Bilinear upscaling of path-traced images (tools/image_upscale.h), the path tracer's points
// below one sample per pixel in ddgi-eval --pareto: values against hand-computed bilinear taps.
#include <gtest/gtest.h>

#include "tools/image_upscale.h"

namespace ddgi::tools {
namespace {

// A 2x1 image, red 0 and 100 (tone-mapped 0 and 200), doubled to 4x2: output pixel centres
// 0.5, 1.5, 2.5, 3.5 map to source x -0.25, 0.25, 0.75, 1.25, clamped to [0, 1]: weights of the
// right pixel 0, 0.25, 0.75, 1.
TEST(Upscale, BilinearTapsBetweenPixelCentresAndClampedAtEdges) {
  PathTraceImage image;
  image.width = 2;
  image.height = 1;
  image.samples = 1;
  image.radiance = {0, 1, 2, 1, 100, 1, 2, 1};
  image.ldr = {0, 10, 20, 255, 200, 10, 20, 255};
  const PathTraceImage up = upscaled(image, 4, 2);
  ASSERT_EQ(up.width, 4u);
  ASSERT_EQ(up.height, 2u);
  ASSERT_EQ(up.radiance.size(), 4u * 2u * 4u);
  ASSERT_EQ(up.ldr.size(), 4u * 2u * 4u);
  const float expected_red[4] = {0.0f, 25.0f, 75.0f, 100.0f};
  const int expected_ldr[4] = {0, 50, 150, 200};
  for (uint32_t y = 0; y < 2; ++y) {
    for (uint32_t x = 0; x < 4; ++x) {
      const size_t i = (size_t(y) * 4 + x) * 4;
      EXPECT_FLOAT_EQ(up.radiance[i], expected_red[x]) << x << "," << y;
      EXPECT_FLOAT_EQ(up.radiance[i + 1], 1.0f);  // constant channels stay constant
      EXPECT_EQ(up.ldr[i], expected_ldr[x]) << x << "," << y;
      EXPECT_EQ(up.ldr[i + 3], 255);
    }
  }
}

// Same size: the image unchanged.
TEST(Upscale, SameSizeIsTheIdentity) {
  PathTraceImage image{3, 2, 4, {}, {}};
  for (int i = 0; i < 3 * 2 * 4; ++i) {
    image.radiance.push_back(float(i) * 0.5f);
    image.ldr.push_back(uint8_t(i * 7));
  }
  const PathTraceImage same = upscaled(image, 3, 2);
  EXPECT_EQ(same.radiance, image.radiance);
  EXPECT_EQ(same.ldr, image.ldr);
  EXPECT_EQ(same.samples, 4u);
}

}  // namespace
}  // namespace ddgi::tools
