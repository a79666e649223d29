// vk::download_image: an image's texels come back exactly as uploaded, from the layout the
// caller names, and a download of the wrong size is refused before any GPU work.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/gpu/gpu_test.h"
#include "vk/resources.h"

namespace ddgi::test {
namespace {

class DownloadImageTest : public GpuTest {};

// In GENERAL (the default: the fields' atlases) and in another layout the caller names.
TEST_F(DownloadImageTest, ReturnsTheUploadedTexels) {
  constexpr uint32_t kWidth = 5, kHeight = 3;
  std::vector<float> texels(kWidth * kHeight * 2);
  for (size_t i = 0; i < texels.size(); ++i) texels[i] = float(i) * 0.25f - 1.0f;
  const auto* bytes = reinterpret_cast<const uint8_t*>(texels.data());
  for (VkImageLayout layout : {VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL}) {
    SCOPED_TRACE(layout);
    auto image = vk::Image::create_2d(context(), kWidth, kHeight, VK_FORMAT_R32G32_SFLOAT,
                                      VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                          VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                      "download test");
    ASSERT_TRUE(image.ok()) << image.error().message;
    ASSERT_TRUE(
        vk::upload_image(context(), *image, {bytes, texels.size() * sizeof(float)}, layout).ok());

    std::vector<float> back(texels.size(), -99.0f);
    const Status status =
        layout == VK_IMAGE_LAYOUT_GENERAL
            ? vk::download_image(context(), *image, back.data(), back.size() * sizeof(float))
            : vk::download_image(context(), *image, back.data(), back.size() * sizeof(float),
                                 layout);
    ASSERT_TRUE(status.ok()) << status.error().message;
    EXPECT_EQ(back, texels);
  }
}

TEST_F(DownloadImageTest, RefusesAWrongSize) {
  auto image = vk::Image::create_2d(context(), 4, 4, VK_FORMAT_R32G32B32A32_SFLOAT,
                                    VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                    "download size test");
  ASSERT_TRUE(image.ok()) << image.error().message;
  std::vector<float> out(4 * 4 * 2);  // half of what the image holds
  const Status status =
      vk::download_image(context(), *image, out.data(), out.size() * sizeof(float));
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().message.find("expected 256"), std::string::npos)
      << status.error().message;
}

}  // namespace
}  // namespace ddgi::test
