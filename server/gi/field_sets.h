// What every probe field (irradiance, shadow, and the field kinds to come) has besides its own
// update passes: three descriptor sets — sampling (what frames and other fields read), update
// (set 1 of its update kernels) and query (set 1 of its query kernel) — the query kernel and the
// one way to run it, the timer of standalone updates, the atlas sampler, and the rule by which
// new parameters replace the old. Written once here so that the fields declare only what
// differs: their bindings, kernels and resources.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"
#include "gpu_scene/gpu_scene.h"
#include "vk/context.h"
#include "vk/pass.h"
#include "vk/pipeline.h"
#include "vk/resources.h"
#include "vk/timer.h"

namespace ddgi {

struct FieldSetsDesc {
  std::string name;  // "field", "shadow field": names the sets and the sampler
  std::vector<vk::Binding> sampling;
  std::vector<vk::Binding> update;
  std::vector<vk::Binding> query;  // exactly two: the inputs, then the answers
  std::string query_kernel;
  bool query_traces = false;
  uint32_t push_constant_bytes = 0;  // of the query and update kernels
  glm::uvec3 workgroup{64, 1, 1};
  uint32_t timed_passes = 16;  // per standalone update submission
};

class FieldSets {
 public:
  FieldSets() = default;
  static Result<FieldSets> create(vk::Context& context, const GpuScene& scene,
                                  const FieldSetsDesc& desc, vk::TraceBackend backend);

  VkDescriptorSetLayout sampling_layout() const { return sampling_layout_.handle(); }
  VkDescriptorSet sampling_set() const { return sampling_set_; }
  VkDescriptorSet update_set() const { return update_set_; }
  // The set layouts of update kernels: the scene (0), the update set (1), the sampling set (2).
  std::vector<VkDescriptorSetLayout> update_layouts() const;
  const vk::Sampler& sampler() const { return sampler_; }
  vk::GpuTimer& timer() { return timer_; }

  // Runs the query kernel once per input: uploads `inputs`, records `before` (e.g. a constants
  // upload) then the kernel with the push constants `push(count, row_width)`, and returns the
  // answers.
  template <typename In, typename Out>
  Result<std::vector<Out>> query(
      const std::vector<In>& inputs,
      const std::function<std::vector<uint8_t>(uint32_t count, uint32_t row_width)>& push,
      std::vector<vk::Pass> before = {});

 private:
  Status run_query(const vk::Buffer& in, const vk::Buffer& out, uint32_t count,
                   const std::function<std::vector<uint8_t>(uint32_t, uint32_t)>& push,
                   std::vector<vk::Pass> before);

  vk::Context* context_ = nullptr;
  const GpuScene* scene_ = nullptr;
  FieldSetsDesc desc_;
  vk::DescriptorLayout sampling_layout_;
  vk::DescriptorLayout update_layout_;
  vk::DescriptorLayout query_layout_;
  VkDescriptorSet sampling_set_ = VK_NULL_HANDLE;
  VkDescriptorSet update_set_ = VK_NULL_HANDLE;
  VkDescriptorSet query_set_ = VK_NULL_HANDLE;  // rewritten by every query
  vk::Kernel query_kernel_;
  vk::GpuTimer timer_;
  vk::Sampler sampler_;
};

// Replaces a field's parameters. `rebuild`: the new ones need new GPU resources. A rebuild the
// budget refuses (`check_budget` of the new parameters) changes nothing, so the old field and
// its history keep running; a rebuild that fails after the old resources were freed (another
// session took memory meanwhile) falls back to the old parameters, starting over.
template <typename Params>
Status replace_params(Params& current, const Params& next, bool rebuild,
                      const std::function<Status(const Params&)>& check_budget,
                      const std::function<Status()>& create_resources) {
  if (rebuild) DDGI_TRY(check_budget(next));
  const Params old = current;
  current = next;
  const Status status = rebuild ? create_resources() : ok_status();
  if (!status.ok()) {
    current = old;
    DDGI_TRY(create_resources());
    return status.error();
  }
  return ok_status();
}

template <typename In, typename Out>
Result<std::vector<Out>> FieldSets::query(
    const std::vector<In>& inputs,
    const std::function<std::vector<uint8_t>(uint32_t count, uint32_t row_width)>& push,
    std::vector<vk::Pass> before) {
  if (inputs.empty()) return std::vector<Out>{};
  DDGI_ASSIGN_OR_RETURN(vk::Buffer in,
                        vk::upload_vector<In>(*context_, inputs, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                              desc_.name + " queries"));
  DDGI_ASSIGN_OR_RETURN(
      vk::Buffer out,
      vk::Buffer::create(*context_, inputs.size() * sizeof(Out),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                         vk::MemoryUsage::kDeviceLocal, desc_.name + " answers"));
  DDGI_TRY(run_query(in, out, static_cast<uint32_t>(inputs.size()), push, std::move(before)));
  std::vector<Out> answers(inputs.size());
  DDGI_TRY(vk::download_buffer(*context_, out, answers.data(), answers.size() * sizeof(Out)));
  return answers;
}

}  // namespace ddgi
