// Texel sizes and float channel counts of the image formats the project makes: what
// vk::download_image checks a download's size against, and how atlas dumps learn their channels.
#include <gtest/gtest.h>

#include "vk/resources.h"

namespace ddgi::vk {
namespace {

TEST(ImageFormats, FloatFormatsHaveFourBytesPerChannel) {
  EXPECT_EQ(float_channels(VK_FORMAT_R32_SFLOAT), 1u);
  EXPECT_EQ(float_channels(VK_FORMAT_R32G32_SFLOAT), 2u);
  EXPECT_EQ(float_channels(VK_FORMAT_R32G32B32A32_SFLOAT), 4u);
  EXPECT_EQ(texel_bytes(VK_FORMAT_R32G32_SFLOAT), 8u);
  EXPECT_EQ(texel_bytes(VK_FORMAT_R32G32B32A32_SFLOAT), 16u);
}

TEST(ImageFormats, EightBitFormatsAreNotFloat) {
  EXPECT_EQ(texel_bytes(VK_FORMAT_R8G8B8A8_UNORM), 4u);
  EXPECT_EQ(texel_bytes(VK_FORMAT_R8G8B8A8_SRGB), 4u);
  EXPECT_EQ(float_channels(VK_FORMAT_R8G8B8A8_UNORM), 0u);
}

TEST(ImageFormats, UnknownFormatsHaveNoSize) {
  EXPECT_EQ(texel_bytes(VK_FORMAT_UNDEFINED), 0u);
  EXPECT_EQ(texel_bytes(VK_FORMAT_R16G16B16A16_SFLOAT), 0u);
  EXPECT_EQ(float_channels(VK_FORMAT_R16G16B16A16_SFLOAT), 0u);
}

}  // namespace
}  // namespace ddgi::vk
