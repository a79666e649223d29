// Command buffers submitted without waiting (vk/command_slot.h).
#include "vk/command_slot.h"

#include <utility>

#include "core/log.h"
#include "vk/check.h"

namespace ddgi::vk {

Result<CommandSlot> CommandSlot::create(Context& context, const std::string& name) {
  CommandSlot slot;
  slot.context_ = &context;
  VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool_info.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  pool_info.queueFamilyIndex = context.queue_family();
  VK_TRY(vkCreateCommandPool(context.device(), &pool_info, nullptr, &slot.pool_));
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = slot.pool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VK_TRY(vkAllocateCommandBuffers(context.device(), &alloc, &slot.cmd_));
  VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VK_TRY(vkCreateFence(context.device(), &fence_info, nullptr, &slot.fence_));
  context.set_name(reinterpret_cast<uint64_t>(slot.cmd_), VK_OBJECT_TYPE_COMMAND_BUFFER, name);
  context.set_name(reinterpret_cast<uint64_t>(slot.fence_), VK_OBJECT_TYPE_FENCE, name);
  return slot;
}

CommandSlot& CommandSlot::operator=(CommandSlot&& other) noexcept {
  if (this != &other) {
    reset();
    context_ = std::exchange(other.context_, nullptr);
    pool_ = std::exchange(other.pool_, VK_NULL_HANDLE);
    cmd_ = std::exchange(other.cmd_, VK_NULL_HANDLE);
    fence_ = std::exchange(other.fence_, VK_NULL_HANDLE);
    serial_ = std::exchange(other.serial_, 0);
    recording_ = std::exchange(other.recording_, false);
  }
  return *this;
}

void CommandSlot::reset() {
  if (!context_) return;
  if (pending()) {
    const Status waited = wait();
    if (!waited.ok()) {
      LOG_ERROR << "command slot: " << waited.error().message;
    }
  }
  VkDevice device = context_->device();
  VkCommandPool pool = pool_;
  VkFence fence = fence_;
  context_->defer_destroy([device, pool, fence] {
    if (fence) vkDestroyFence(device, fence, nullptr);
    if (pool) vkDestroyCommandPool(device, pool, nullptr);  // frees its command buffer
  });
  context_ = nullptr;
  pool_ = VK_NULL_HANDLE;
  cmd_ = VK_NULL_HANDLE;
  fence_ = VK_NULL_HANDLE;
  recording_ = false;
}

Result<VkCommandBuffer> CommandSlot::begin() {
  if (!context_) return failed_precondition("command slot used before it was created");
  if (pending() || recording_) {
    return failed_precondition("command slot re-recorded while its submission is in flight");
  }
  VK_TRY(vkResetCommandPool(context_->device(), pool_, 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_TRY(vkBeginCommandBuffer(cmd_, &begin));
  recording_ = true;
  return cmd_;
}

Status CommandSlot::submit() {
  if (!recording_) return failed_precondition("command slot submitted without recording");
  recording_ = false;
  VK_TRY(vkEndCommandBuffer(cmd_));
  VK_TRY(vkResetFences(context_->device(), 1, &fence_));
  VkSubmitInfo info{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  info.commandBufferCount = 1;
  info.pCommandBuffers = &cmd_;
  DDGI_ASSIGN_OR_RETURN(serial_, context_->submit(info, fence_));
  return ok_status();
}

Status CommandSlot::wait() {
  if (!pending()) return ok_status();
  const uint64_t serial = std::exchange(serial_, 0);
  return context_->wait(serial, fence_);
}

}  // namespace ddgi::vk
