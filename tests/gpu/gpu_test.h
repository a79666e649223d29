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
    EXPECT_EQ(gpu_context().validation_message_count(), messages_before_)
        << "Vulkan validation reported problems during this test (see the log above)";
  }
  vk::Context& context() { return gpu_context(); }

 private:
  uint32_t messages_before_ = 0;
};

}  // namespace ddgi::test
