// Recording of pass lists (vk/pass.h).
#include "vk/pass.h"

namespace ddgi::vk {

void record_passes(VkCommandBuffer cmd, GpuTimer* timer, std::span<const Pass> passes) {
  for (const Pass& pass : passes) {
    const bool timed = timer && pass.timed;
    if (timed) timer->begin_pass(cmd, pass.name, pass.group);
    if (pass.kernel) {
      pass.kernel->dispatch(cmd, pass.sets,
                            pass.push_constants.empty() ? nullptr : pass.push_constants.data(),
                            pass.size);
    } else if (pass.commands) {
      pass.commands(cmd);
    }
    if (timed) timer->end_pass(cmd);
    barrier_all(cmd);
  }
}

}  // namespace ddgi::vk
