// GPU timestamps around named passes of one submission.
#pragma once

#include <vulkan/vulkan.h>

#include <string>
#include <vector>

#include "core/result.h"
#include "vk/context.h"

namespace ddgi::vk {

struct PassTime {
  std::string name;
  double milliseconds = 0.0;
};

class GpuTimer {
 public:
  GpuTimer() = default;
  static Result<GpuTimer> create(Context& context, uint32_t max_passes);
  ~GpuTimer() { reset(); }
  GpuTimer(GpuTimer&& other) noexcept { *this = std::move(other); }
  GpuTimer& operator=(GpuTimer&& other) noexcept;
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;
  void reset();

  // Call at the start of recording; clears the previous submission's passes.
  void begin_frame(VkCommandBuffer cmd);
  void begin_pass(VkCommandBuffer cmd, const std::string& name);
  void end_pass(VkCommandBuffer cmd);
  // After the submission completed: the measured passes, in recording order. Empty when the
  // device has no timestamps.
  Result<std::vector<PassTime>> read();

 private:
  Context* context_ = nullptr;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t capacity_ = 0;
  std::vector<std::string> names_;
  bool open_ = false;
};

}  // namespace ddgi::vk
