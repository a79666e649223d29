// Shared fixture for tests that run GPU kernels (on lavapipe in CI). One Vulkan context with
// validation layers on serves the whole test binary; any validation message fails the test
// during which it appeared.
#pragma once

#include <gtest/gtest.h>

#include "vk/context.h"

namespace ddgi::test {

vk::Context& gpu_context();

class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override { messages_before_ = gpu_context().validation_message_count(); }
  void TearDown() override {
    EXPECT_EQ(gpu_context().validation_message_count(), messages_before_ + messages_expected_)
        << "Vulkan validation reported problems during this test (see the log above)";
  }
  vk::Context& context() { return gpu_context(); }
  // For the one test that provokes validation messages on purpose (to show the check above is
  // live): TearDown then requires exactly this many.
  void expect_validation_messages(uint32_t count) { messages_expected_ = count; }
  uint32_t messages_before() const { return messages_before_; }

 private:
  uint32_t messages_before_ = 0;
  uint32_t messages_expected_ = 0;
};

}  // namespace ddgi::test
