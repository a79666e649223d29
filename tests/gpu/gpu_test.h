// Shared fixture for tests that run GPU kernels (on lavapipe in CI). One Vulkan context with
// validation layers on serves the whole test binary; any validation message fails the test
// during which it appeared.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

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

// The spread of a result: over the first `channels` of every `stride` values (RGB of an RGBA
// image: 4, 3; all values: 1, 1).
struct ValueSpread {
  double mean = 0.0;
  double min = 0.0;
  double max = 0.0;
  size_t count = 0;
};
ValueSpread value_spread(const std::vector<float>& values, size_t stride = 1, size_t channels = 1);

// Two backends that agree, or a result within a tolerance of another, prove nothing when the
// result is trivial: a pass that writes nothing gives two equal black images, a field that never
// updates two equal initial atlases. Comparisons assert this on one side: a mean of at least
// `min_mean` (not black) and max - min of at least `min_range` (not one value everywhere, e.g. the
// initial state); non-finite values fail it. The message gives what was measured.
::testing::AssertionResult is_nontrivial(const std::vector<float>& values, double min_mean,
                                         double min_range, size_t stride = 1, size_t channels = 1);

}  // namespace ddgi::test
