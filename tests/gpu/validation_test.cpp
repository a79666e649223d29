// The suite's "no validation messages" check (GpuTest::TearDown) is only worth something if
// messages reach the counter. This test breaks a rule on purpose and watches the count rise.
#include <gtest/gtest.h>

#include <vulkan/vulkan.h>

#include "tests/gpu/gpu_test.h"

namespace ddgi::test {
namespace {

class ValidationSelfTest : public GpuTest {};

TEST_F(ValidationSelfTest, AKnownErrorRaisesTheMessageCounter) {
  ASSERT_TRUE(context().validation_enabled());
  const uint32_t before = context().validation_message_count();
  EXPECT_EQ(before, messages_before());

  // A buffer with no usage flags breaks VUID-VkBufferCreateInfo-usage-requiredbitmask (an
  // implicit-validity rule every layer version checks). lavapipe creates it anyway, so it is
  // destroyed normally afterwards; nothing is submitted.
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = 256;
  info.usage = 0;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer buffer = VK_NULL_HANDLE;
  const VkResult result = vkCreateBuffer(context().device(), &info, nullptr, &buffer);
  if (result == VK_SUCCESS && buffer != VK_NULL_HANDLE) {
    vkDestroyBuffer(context().device(), buffer, nullptr);
  }

  const uint32_t after = context().validation_message_count();
  EXPECT_GT(after, before) << "the validation layer did not report an invalid VkBufferCreateInfo";
  // TearDown's check must see exactly these messages, no others.
  expect_validation_messages(after - before);
}

}  // namespace
}  // namespace ddgi::test
