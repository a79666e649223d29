// A pass: one step of GPU work declared as data (its name, timing group, kernel, descriptor
// sets, push constants, dispatch size, and the resources it reads and writes), and the one
// function that records a list of them. Renderer, both fields and the path tracer describe
// their work as pass lists; callers concatenate lists (a field update, then a frame) into one
// submission. Passes are separated by full barriers today; the declared reads and writes are
// what a later, local change needs to narrow them.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <cstring>
#include <functional>
#include <span>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

#include "vk/pipeline.h"
#include "vk/resources.h"
#include "vk/timer.h"

namespace ddgi::vk {

// A GPU resource a pass reads or writes.
using ResourceRef = std::variant<const Buffer*, const Image*>;

struct Pass {
  std::string name;  // what the timer and debug labels call it, e.g. "field trace"
  PassGroup group = PassGroup::kFrame;
  // Either a kernel dispatch (kernel, sets, push constants, size) ...
  const Kernel* kernel = nullptr;
  std::vector<VkDescriptorSet> sets;
  std::vector<uint8_t> push_constants;
  glm::uvec3 size{0, 0, 0};  // invocations (threads, or rays on the pipeline backend)
  // ... or transfer commands (buffer updates, copies) when `kernel` is null.
  std::function<void(VkCommandBuffer)> commands;
  std::vector<ResourceRef> reads;
  std::vector<ResourceRef> writes;
  // Untimed passes (constant uploads) get no timestamp and no entry in the pass times.
  bool timed = true;

  // The bytes of a push-constant struct.
  template <typename T>
  static std::vector<uint8_t> push(const T& constants) {
    std::vector<uint8_t> bytes(sizeof(T));
    std::memcpy(bytes.data(), &constants, sizeof(T));
    return bytes;
  }
};

// `pass` with its declared reads and writes.
inline Pass with_access(Pass pass, std::vector<ResourceRef> reads,
                        std::vector<ResourceRef> writes) {
  pass.reads = std::move(reads);
  pass.writes = std::move(writes);
  return pass;
}

// Records `passes` in order: each timed pass between timestamps of its name and group (when
// `timer` is not null), then a full barrier.
void record_passes(VkCommandBuffer cmd, GpuTimer* timer, std::span<const Pass> passes);

// A pass that uploads `constants` into `buffer` (vkCmdUpdateBuffer: at most 64 KiB).
template <typename T>
Pass upload_pass(std::string name, PassGroup group, const Buffer& buffer, const T& constants) {
  static_assert(sizeof(T) % 4 == 0 && sizeof(T) <= 65536, "vkCmdUpdateBuffer limits");
  Pass pass;
  pass.name = std::move(name);
  pass.group = group;
  pass.timed = false;
  pass.writes = {&buffer};
  pass.commands = [handle = buffer.handle(), constants](VkCommandBuffer cmd) {
    vkCmdUpdateBuffer(cmd, handle, 0, sizeof(T), &constants);
  };
  return pass;
}

}  // namespace ddgi::vk
