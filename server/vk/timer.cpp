#include "vk/timer.h"

#include "vk/check.h"

namespace ddgi::vk {

Result<GpuTimer> GpuTimer::create(Context& context, uint32_t max_passes) {
  GpuTimer timer;
  timer.context_ = &context;
  if (!context.caps().timestamps) return timer;
  timer.capacity_ = max_passes;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = max_passes * 2;
  VK_TRY(vkCreateQueryPool(context.device(), &info, nullptr, &timer.pool_));
  context.set_name(reinterpret_cast<uint64_t>(timer.pool_), VK_OBJECT_TYPE_QUERY_POOL,
                   "pass timestamps");
  return timer;
}

GpuTimer& GpuTimer::operator=(GpuTimer&& other) noexcept {
  if (this != &other) {
    reset();
    context_ = std::exchange(other.context_, nullptr);
    pool_ = std::exchange(other.pool_, VK_NULL_HANDLE);
    capacity_ = other.capacity_;
    passes_ = std::move(other.passes_);
    open_ = other.open_;
  }
  return *this;
}

void GpuTimer::reset() {
  if (context_ && pool_) {
    VkDevice device = context_->device();
    VkQueryPool pool = pool_;
    context_->defer_destroy([device, pool] { vkDestroyQueryPool(device, pool, nullptr); });
  }
  context_ = nullptr;
  pool_ = VK_NULL_HANDLE;
  passes_.clear();
}

void GpuTimer::begin_frame(VkCommandBuffer cmd) {
  passes_.clear();
  open_ = false;
  if (pool_) vkCmdResetQueryPool(cmd, pool_, 0, capacity_ * 2);
}

void GpuTimer::begin_pass(VkCommandBuffer cmd, const std::string& name, PassGroup group) {
  if (context_ && context_->fn().vkCmdBeginDebugUtilsLabelEXT) {
    VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
    label.pLabelName = name.c_str();
    context_->fn().vkCmdBeginDebugUtilsLabelEXT(cmd, &label);
  }
  open_ = true;
  if (!pool_ || passes_.size() >= capacity_) return;
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool_,
                      static_cast<uint32_t>(passes_.size()) * 2);
  passes_.emplace_back(name, group);
}

void GpuTimer::end_pass(VkCommandBuffer cmd) {
  if (!open_) return;
  open_ = false;
  if (context_ && context_->fn().vkCmdEndDebugUtilsLabelEXT) {
    context_->fn().vkCmdEndDebugUtilsLabelEXT(cmd);
  }
  if (!pool_ || passes_.empty() || passes_.size() > capacity_) return;
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_,
                      static_cast<uint32_t>(passes_.size()) * 2 - 1);
}

Result<std::vector<PassTime>> GpuTimer::read() {
  std::vector<PassTime> times;
  if (!pool_ || passes_.empty()) return times;
  std::vector<uint64_t> ticks(passes_.size() * 2);
  VK_TRY(vkGetQueryPoolResults(context_->device(), pool_, 0, static_cast<uint32_t>(ticks.size()),
                               ticks.size() * sizeof(uint64_t), ticks.data(), sizeof(uint64_t),
                               VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  const double ns_per_tick = context_->caps().timestamp_period_ns;
  for (size_t i = 0; i < passes_.size(); ++i) {
    const uint64_t begin = ticks[2 * i];
    const uint64_t end = ticks[2 * i + 1];
    const double ms = end >= begin ? double(end - begin) * ns_per_tick * 1e-6 : 0.0;
    times.push_back({passes_[i].first, ms, passes_[i].second});
  }
  return times;
}

double group_milliseconds(const std::vector<PassTime>& times, PassGroup group) {
  double sum = 0.0;
  for (const PassTime& t : times) {
    if (t.group == group) sum += t.milliseconds;
  }
  return sum;
}

}  // namespace ddgi::vk
