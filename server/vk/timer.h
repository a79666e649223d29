// GPU timestamps around named passes of one submission. Each pass carries the group it was
// declared in (vk::Pass::group), so totals per group never depend on names or positions.
#pragma once

#include <vulkan/vulkan.h>

#include <string>
#include <vector>

#include "core/result.h"
#include "vk/context.h"

namespace ddgi::vk {

// What a pass's time counts towards. Tools and the service sum pass times by group: the field
// update's ms (and its Mrays/s) must not include the shadow field's passes, and so on.
enum class PassGroup : uint8_t {
  kShadowField,      // shadow-field update
  kIrradianceField,  // irradiance-field update
  kFrame,            // the frame's own passes (primary, direct, indirect, views, tone mapping)
  kReadback,         // copies of results to host-visible memory
  kBaseline,         // ddgi-bench's raw-ray baselines: part of no update and no frame
};

struct PassTime {
  std::string name;
  double milliseconds = 0.0;
  PassGroup group = PassGroup::kFrame;
};
// The summed milliseconds of the passes of `group`.
double group_milliseconds(const std::vector<PassTime>& times, PassGroup group);

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
  void begin_pass(VkCommandBuffer cmd, const std::string& name, PassGroup group);
  void end_pass(VkCommandBuffer cmd);
  // After the submission completed: the measured passes, in recording order. Empty when the
  // device has no timestamps.
  Result<std::vector<PassTime>> read();

 private:
  Context* context_ = nullptr;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t capacity_ = 0;
  std::vector<std::pair<std::string, PassGroup>> passes_;
  bool open_ = false;
};

}  // namespace ddgi::vk
