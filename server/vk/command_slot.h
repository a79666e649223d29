// A command buffer of its own (pool, buffer, fence) for GPU work that is submitted now and
// waited for later: a frame target records each of its frames into one, so a session can
// record and submit the next frame while the GPU still runs the previous one. Recording and
// waiting hold no lock; only the submission takes the context's queue lock (Context::submit).
// Also what Context::submit_and_wait draws its one-shot buffers from.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>

#include "core/result.h"
#include "vk/context.h"

namespace ddgi::vk {

class CommandSlot {
 public:
  CommandSlot() = default;
  // `name` labels the buffer in validation messages and debuggers.
  static Result<CommandSlot> create(Context& context, const std::string& name);
  ~CommandSlot() { reset(); }
  CommandSlot(CommandSlot&& other) noexcept { *this = std::move(other); }
  CommandSlot& operator=(CommandSlot&& other) noexcept;
  CommandSlot(const CommandSlot&) = delete;
  CommandSlot& operator=(const CommandSlot&) = delete;
  // Waits for a pending submission, then hands the handles to deferred destruction.
  void reset();

  // Starts recording into the (reset) command buffer. FAILED_PRECONDITION while the previous
  // submission is pending: its buffer must not be re-recorded before the GPU is done with it.
  Result<VkCommandBuffer> begin();
  // Ends recording and submits; returns without waiting.
  Status submit();
  // Waits for the pending submission, holding no lock; nothing to do when none is pending.
  Status wait();
  // Submitted and not yet waited for.
  bool pending() const { return serial_ != 0; }
  explicit operator bool() const { return pool_ != VK_NULL_HANDLE; }

 private:
  Context* context_ = nullptr;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  uint64_t serial_ = 0;  // the pending submission's (Context::submit), 0 when none
  bool recording_ = false;
};

}  // namespace ddgi::vk
